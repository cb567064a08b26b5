#pragma once
// Which object a task means, in words the agent can resolve: the item on its source platform
// and the anchors on the destination are each named by a reference (referring.h) that picks out
// exactly that instance in the state the step starts from (and, for anchors, also once the item
// is in hand, when the agent chooses where to put it). A goal with look-alikes is Level 2; one
// whose objects cannot be told apart by any reference is not generated.

#include <optional>
#include <string>
#include <vector>

#include "core/episode/goals.h"
#include "core/tasks/reference_memo.h"
#include "core/tasks/referring.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

/// The references a text uses for an atomic goal's objects.
struct Wording {
  Reference item;
  Reference anchor;   // unused when the goal has no anchor
  Reference anchor2;  // between only
};

struct Identified {
  Wording wording;
  std::vector<Identification> lookalikes;  // the objects whose reference is not "alone"
};

/// The wording of a goal, or why there is none.
struct Naming {
  std::optional<Identified> identified;
  /// An object is named in the geometry but not in what its platform's arrival view shows
  /// (counted as `occluded`; otherwise `unidentifiable`).
  bool occluded = false;

  explicit operator bool() const { return identified.has_value(); }
  const Identified* operator->() const { return &*identified; }
  const Identified& operator*() const { return *identified; }
};

/// The wording of `goal` in state `start` (nothing held): the item as its source's arrival view
/// shows it, the anchors as the destination's does with the item in hand (and, when the item
/// comes from there, before it is picked). `part` is recorded in the identifications (Level 3
/// sub-task index). `memo`, when given, must use `rule` and `seeing`; the words are the same
/// with or without it.
Naming identify(const graph::SceneGraph& g, const episode::WorldState& start, const episode::AtomicGoal& goal,
                Ambiguity rule, int part = 0, const ReferenceMemo* memo = nullptr,
                const render::VisibilityOracle* seeing = nullptr);

/// Whether some object of the goal has a look-alike (the Level 2 test), without building
/// references: cheap enough for counting dropped tasks.
bool has_lookalikes(const graph::SceneGraph& g, const episode::WorldState& start, const episode::AtomicGoal& goal,
                    Ambiguity rule);

/// The identification record of `object` named by `r` on `platform`.
Identification make_identification(const graph::SceneGraph& g, int part, const std::string& role,
                                   graph::ObjectId object, graph::PlatformId platform, const Reference& r);

}  // namespace mtg::tasks
