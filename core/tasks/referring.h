#pragma once
// Referring expressions: how a task text names one object among look-alikes on a platform, so
// that a Level 2 task ("the teacup, on a table with several teacups") is solvable from what the
// agent is given (the paper, §4: "task-provided descriptions or images").
//
// A noun is what the ambiguity rule compares (Ambiguity::kCategory: "book"; kNameWithoutId:
// "book 01"). A reference adds at most one relation, evaluated on the furniture platform the
// object stands on (at any depth), among the objects with the same noun (the candidates):
//
//   alone      "the book"                 the only candidate
//   on         "the book on the box"      it rests on an object called <landmark>
//   under      "the box under the book"   an object called <landmark> rests on it
//   next_to    "the book next to the lamp" its footprint is within 5 cm of a <landmark>'s and no
//                                         other candidate's is within 15 cm of any <landmark>
//   from_left, from_right (rank 1..4)
//              "the leftmost book", "the third book from the right": counting candidates along
//                                         that axis by footprint centre, every centre up to the
//                                         one after it at least 3 cm from the next
//   nearest, farthest
//              "the nearest book"         the same along the near-far axis, rank 1 only
//
// Left, right, near and far are named as seen from the platform's arrival side (the side `l<N>`
// brings the robot to, Platform::default_side), so every agent reads them alike.
// resolve() is the geometric test a reader applies; refer() picks the first relation, in the
// order above, that resolve() finds to name exactly the object in every state given and that
// the arrival view shows (with a VisibilityOracle): the object and its landmark clearly
// visible; for a rank, nearest or farthest every candidate clearly visible, in the picture in
// the order the footprints give, each of the neighbours counted at least min_gap pixels from the
// next (left/right along the image's width, near/far along its height: nearer is lower).

#include <optional>
#include <string>
#include <vector>

#include "core/episode/world_state.h"
#include "core/render/visibility.h"
#include "core/tasks/reference.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

/// The words for an object under the ambiguity rule: its noun ("sponge dish", from the scene
/// profile; its category where the profile has none), its category ("kitchen utensil"), or its
/// name without instance id ("kitchen utensil 09"); the display name when it has no category.
std::string noun_of(const graph::GraphObject& o, Ambiguity rule);

/// The objects on furniture platform `platform` (at any depth) that `r` picks out in `s`: exactly
/// one when the reference is good there.
std::vector<graph::ObjectId> resolve(const graph::SceneGraph& g, const episode::WorldState& s,
                                     graph::PlatformId platform, const Reference& r, Ambiguity rule);

/// Whether `object` has look-alikes on `platform` in `s` (another object with its noun).
bool has_lookalike(const graph::SceneGraph& g, const episode::WorldState& s, graph::ObjectId object,
                   graph::PlatformId platform, Ambiguity rule);

/// Whether `sight`, an arrival view of `platform` in `s`, shows what reference `r` to `object`
/// needs (the rule above, with `min_gap` image pixels between counted neighbours).
bool seen_as(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
             graph::ObjectId object, const Reference& r, Ambiguity rule, std::shared_ptr<const render::ViewSight> sight,
             double min_gap);

/// A reference, or why there is none.
struct Referral {
  std::optional<Reference> reference;
  /// Some reference names the object in the geometry, but none in what the arrival view shows.
  bool occluded = false;

  explicit operator bool() const { return reference.has_value(); }
  const Reference& operator*() const { return *reference; }
  const Reference* operator->() const { return &*reference; }
};

/// A reference naming exactly `object` on `platform` in every state of `states`, and, with
/// `seeing`, in what the arrival view of each state shows.
Referral refer(const graph::SceneGraph& g, const std::vector<const episode::WorldState*>& states,
               graph::ObjectId object, graph::PlatformId platform, Ambiguity rule,
               const render::VisibilityOracle* seeing = nullptr);

}  // namespace mtg::tasks
