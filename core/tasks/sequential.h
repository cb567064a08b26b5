#pragma once
// Level 3, the paper's progressive version (not the release's random pairing): sample an atomic
// task, apply its placement to a copy of the world, sample the next task among those feasible in
// the new state, and join them with "then". A chain is kept only if, after its last step, every
// earlier goal still holds (by at least the placement margin), so the judge can score all of
// them at the end; no step's goal may already hold when that step starts, and every object of a
// step must be nameable in the state the step starts from (identify.h).
//
// Sampling the next task: with probability 1/2 a uniformly drawn atomic task of the initial state
// whose item has not moved yet, re-planned only if it touches a platform that changed (the rest
// stay valid as they are); otherwise a "chained" task that uses an already moved object as its
// anchor, found by enumerating one random item against the platform that object now stands on.
// Only the platforms that changed are ever re-evaluated.

#include <functional>
#include <vector>

#include "core/tasks/atomic.h"
#include "core/tasks/identify.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

struct Sequence {
  std::vector<AtomicTask> parts;   // each with its oracle valid in the state the previous left
  std::vector<Identified> words;   // how each part's text names its objects, in its start state
};

/// Takes each chain as it is drawn, in order.
using SequenceSink = std::function<void(Sequence)>;

/// `count` distinct chains of `options.level3_chain` parts, handed to `take` in order (2,048
/// drawn at a time, so the whole set is never held), deterministic in options.seed and
/// the same for any number of `jobs` (threads drawing chains) and with or without `memo`. With
/// `seeing`, each step's objects are named only as their arrival views show them in the state
/// the step starts from (identify.h).
void generate_sequences(const graph::SceneGraph& g, const episode::WorldState& initial,
                        const std::vector<AtomicTask>& atomic, int count, const TaskOptions& options,
                        std::vector<std::string>& warnings, DropCounts& dropped, int jobs, const SequenceSink& take,
                        episode::PlacementMemo* memo = nullptr, const render::VisibilityOracle* seeing = nullptr);

}  // namespace mtg::tasks
