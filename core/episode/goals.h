#pragma once
// Goal predicates evaluated on a world state: the geometric success tests of the judge, and the
// tests task generation uses to decide which goals a placement achieves (so every generated task
// is, by construction, a goal the judge will accept).
//
// Atomic goals (Levels 1-3), with the item standing on `platform`, not held:
//   surface       anywhere on the platform
//   surface_part  footprint centre strictly inside the named 3x3 cell
//   around        footprint within around_distance of the anchor's footprint
//   direction     footprint centre strictly in the anchor's named direction: beyond the anchor's
//                 edge and within its extent across (sides), or beyond both edges (corners)
//   between       footprint centre strictly in the corridor between the two anchors: between
//                 their facing edges and within the overlap of their extents across
//
// Direction convention (docs/episode.md): parts and directions are egocentric at placement,
// named from the side the robot stood at when it put the item down ("front" is the part
// farthest from it, "left" its left). An item the episode never placed has no such side, so a
// surface_part or direction goal about it does not hold: no task is won without acting.
//
// Outcome goals (Level 4) are conjunctions of set predicates (all_on, none_on, near, together,
// any_pair_near, count_on, apart, all_near, none_near).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/episode/world_state.h"

namespace mtg::episode {

enum class GoalType { kSurface, kSurfacePart, kAround, kDirection, kBetween };
const char* to_string(GoalType type);
/// @throws mtg::Error for an unknown name.
GoalType goal_type_from_string(const std::string& name);

struct GoalOptions {
  double around_distance = 0.10;  // m, gap between footprints
};

struct AtomicGoal {
  GoalType type = GoalType::kSurface;
  graph::ObjectId item;
  graph::PlatformId source;    // furniture platform the item starts on (intermediate points)
  graph::PlatformId platform;  // destination
  graph::ObjectId anchor;
  graph::ObjectId anchor2;
  int direction = -1;   // relative direction (surface_part 0..8, direction 0..7)

  /// The anchors this goal names (none, one, or two for "between").
  std::vector<graph::ObjectId> anchors() const;
};

bool goal_satisfied(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal,
                    const GoalOptions& options = {});

/// Whether the goal would hold as the item stands now, named from any side of its platform where
/// the robot can stand: the agent could then meet it by putting the item back where it was, so
/// the generator never asks for it (the triviality test).
bool goal_met_from_any_side(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal,
                            const GoalOptions& options = {});

/// How far (m) the item's footprint centre could move in any direction, in the plane of its
/// platform, before the goal stops holding: 0 when it does not hold, +inf for a surface goal.
/// Robust tasks place the item well inside their goal (docs/tasks.md, "Robust placements").
double goal_margin(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal,
                   const GoalOptions& options = {});

/// The footprint-centre positions (destination platform frame) where the goal would hold for an
/// item of footprint `item_rel_P` (relative to its footprint centre, in platform axes) placed
/// from `side`; clipped to the platform's bounding box. "around" is approximated with a mitred
/// offset. Used for the feasible-area rule of task generation.
geom::Region goal_region_P(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal,
                           graph::Side side, const geom::Ring& item_rel_P, const GoalOptions& options = {});

/// Level 4: a set predicate over objects and platforms.
///   all_on         every object stands on one of `platforms` (at any depth)
///   none_on        no object stands on (or is held above) any of `platforms`
///   near           the two objects stand on one platform within around_distance
///   together       all objects stand on one platform
///   any_pair_near  some object of `objects` and some of `objects2` stand side by side (within
///                  around_distance) on one of `platforms`: "one cup next to one plate"
///   count_on       between `min` and `max` of `objects` (both counts included) stand on one of
///                  `platforms`: "leave exactly two books on the shelf"
///   apart          no two of `objects` stand on one platform, and none is held: "spread out"
///   all_near       every object of `objects` stands side by side with some object of
///                  `objects2` (on its platform): "the cups next to the teapot"
///   none_near      no object of `objects` stands side by side with any of `objects2`: "clear
///                  the space around the lamp"
struct SetPredicate {
  enum class Op { kAllOn, kNoneOn, kNear, kTogether, kAnyPairNear, kCountOn, kApart, kAllNear, kNoneNear };
  Op op = Op::kAllOn;
  std::vector<graph::ObjectId> objects;
  std::vector<graph::PlatformId> platforms;  // all_on: any of these; none_on: none of these
  std::vector<graph::ObjectId> objects2;     // any_pair_near, all_near, none_near: the second group
  int min = 0;                               // count_on
  int max = 0;                               // count_on
};
/// Whether the predicate's second object list is part of what it asks (any_pair_near, all_near,
/// none_near).
bool uses_objects2(SetPredicate::Op op);
const char* to_string(SetPredicate::Op op);

struct OutcomeGoal {
  std::vector<SetPredicate> all;  // conjunction
};

bool predicate_satisfied(const graph::SceneGraph& g, const WorldState& s, const SetPredicate& p,
                         const GoalOptions& options = {});
bool outcome_satisfied(const graph::SceneGraph& g, const WorldState& s, const OutcomeGoal& goal,
                       const GoalOptions& options = {});

/// JSON forms (names, not indices), as stored in goal_json. The from_json functions throw
/// mtg::Error naming the field when a name is unknown to the graph.
nlohmann::json to_json(const graph::SceneGraph& g, const AtomicGoal& goal);
AtomicGoal atomic_goal_from_json(const graph::SceneGraph& g, const nlohmann::json& j);
nlohmann::json to_json(const graph::SceneGraph& g, const OutcomeGoal& goal);
OutcomeGoal outcome_goal_from_json(const graph::SceneGraph& g, const nlohmann::json& j);

/// A stored task goal ({"atomic": ...}, {"sequence": [...]}, {"outcome": ...}) resolved against a
/// graph. @throws mtg::Error naming the field or name that does not resolve.
struct TaskGoal {
  std::vector<AtomicGoal> parts;  // atomic: one; sequence: several (all must hold at the end)
  OutcomeGoal outcome;            // used when `is_outcome`
  bool is_outcome = false;
  /// Objects the agent must not pick: the anchors of every part that no part moves.
  std::vector<graph::ObjectId> protected_objects() const;
};
TaskGoal task_goal_from_json(const graph::SceneGraph& g, const nlohmann::json& goal);
/// Success at the end of an episode: nothing held and every part (or the outcome) satisfied.
bool task_goal_satisfied(const graph::SceneGraph& g, const WorldState& s, const TaskGoal& goal,
                         const GoalOptions& options = {});

/// Distance between two convex footprints (0 when they touch or overlap).
double footprint_gap(const geom::Ring& a, const geom::Ring& b);

/// footprint_gap(a, b) where it is at most `limit`; beyond, some distance above `limit` (the gap
/// between the footprints' boxes, given), without looking at their edges. A test `gap <= d` or
/// `gap > d` for any d <= limit, and the least of several gaps when it is at most `limit`, read
/// the same as with footprint_gap.
double footprint_gap_up_to(const geom::Ring& a, const Eigen::AlignedBox2d& box_a, const geom::Ring& b,
                           const Eigen::AlignedBox2d& box_b, double limit);

}  // namespace mtg::episode
