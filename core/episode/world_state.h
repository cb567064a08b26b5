#pragma once
// The mutable world of one episode (model/data split: the SceneGraph is the const model).
// It records where every object stands now, what the robot holds, where it stands and which way
// it faces. Copying it is cheap (a few hundred objects), which task generation relies on.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/geom/polygon.h"
#include "core/graph/free_space.h"
#include "core/graph/scene_graph.h"
#include "core/util/id_vector.h"

namespace mtg::episode {

struct ObjectState {
  graph::PlatformId parent;         // supporting platform; none: floor/structure or held
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world translation of the object frame
  geom::Ring footprint;             // world xy
  double bottom = 0.0;
  double top = 0.0;
  int placed_side = -1;             // side the robot stood at when it last placed this object
};

/// Phases of the paper's action state machine.
enum class Phase { kStart, kAtPlatform, kPlacing, kDone };

/// How the items on a platform are numbered (the agent's o-keys and the marks in its images)
/// as an episode goes on (issue 53).
///   kStable    an item keeps its number for the whole episode: a picked item's number is
///              retired, never given to another, and an item set down on a platform takes the
///              number after the highest that platform has had (so "number 5 where you picked
///              it up" stays true, and object 5 is the same object at every visit).
///   kPerState  the release's rule: every state numbers its items 1..N afresh, so after a pick
///              the later items move up one. Tasks made before `mtg-tasks/4` were planned with it
///              (their oracle keys of later steps count that way), so their runs keep it.
enum class Numbering : std::int8_t { kStable = 0, kPerState = 1 };
/// "stable", "per_state".
const char* to_string(Numbering numbering);
/// @throws mtg::Error "<what> is stable or per_state, not '<name>'".
Numbering numbering_from_string(std::string_view name, std::string_view what);

struct WorldState {
  IdVector<graph::ObjectId, ObjectState> objects;  // parallel to SceneGraph::objects
  // Per platform, objects resting on it, in order.
  IdVector<graph::PlatformId, std::vector<graph::ObjectId>> children;
  IdVector<graph::PlatformId, Eigen::Vector3d> platform_offset;  // moved item platforms (zero for furniture)
  graph::ObjectId held;                            // object in the robot's hand
  graph::PlatformId at_platform;                   // platform the robot stands at
  int side = -1;                                   // side it stands at (graph::Side as int)
  Phase phase = Phase::kStart;
  int steps = 0;                                   // actions taken (valid or not)
  Numbering numbering = Numbering::kStable;
  // Stable numbering only: per furniture platform whose items have changed, its items by number
  // (entry k is number k + 1; none where a number is retired). Empty for a platform nothing has
  // been picked from or set down on: its numbers are pickable_on's order then.
  IdVector<graph::PlatformId, std::vector<graph::ObjectId>> numbered;
};

/// The scene as the graph found it: nothing held, robot at the start.
WorldState initial_state(const graph::SceneGraph& g, Numbering numbering = Numbering::kStable);

/// Pickable objects on `platform` in the agent's o-numbering: each direct child followed by the
/// objects resting on it (the paper's order); items only (scenery is never picked).
std::vector<graph::ObjectId> pickable_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform);

/// The items on furniture platform `platform` by number: entry k is number k + 1, an invalid id
/// where that number is retired (stable numbering; see Numbering). Without changes, pickable_on.
std::vector<graph::ObjectId> numbered_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform);
/// The number of `object` on `platform` in `s`, 0 when it has none there.
int number_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform, graph::ObjectId object);
/// The number of `object` where it stands (its furniture platform), 0 when it has none.
int number_of(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object);
/// The o-key of `object` where it stands ("o3"), "" when it has no number.
std::string object_key(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object);

/// The centre of an object's footprint (world xy): where it stands, for placement and goals.
geom::Point2 footprint_centre(const ObjectState& o);

/// Objects directly on `platform` (items and scenery): the obstacles for placing there.
const std::vector<graph::ObjectId>& objects_on(const WorldState& s, graph::PlatformId platform);

/// Everything resting on `platform`, directly or on other objects (depth first, direct children
/// in order).
std::vector<graph::ObjectId> everything_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform);

/// Obstacles of `platform` in its frame, in the current state.
std::vector<graph::Obstacle> obstacles_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform);

/// The world frame of a platform now (item platforms move with their owner).
Eigen::Isometry2d platform_frame(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform);
double platform_height(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform);

/// Removes `object` from its platform and puts it in the hand; everything resting on it stays
/// on it (and moves with it). Stable numbering retires their numbers.
void pick(const graph::SceneGraph& g, WorldState& s, graph::ObjectId object);

/// Puts the held object on `platform` with its reference point (the object-frame origin) at
/// `xy` (world), its bottom on the surface; records the side used. Descendants move along.
/// Stable numbering gives it and its descendants the next numbers of the furniture platform.
void place_held(const graph::SceneGraph& g, WorldState& s, graph::PlatformId platform, const Eigen::Vector2d& xy);

/// Everything resting on `object`, directly or on other objects: what moves with it (each of its
/// platforms' everything_on, in turn).
std::vector<graph::ObjectId> resting_on(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object);
/// The held object and everything resting on it (what it carries along): none of it is drawn where
/// it stood, since it is in the hand. Empty when nothing is held.
std::vector<graph::ObjectId> in_hand(const graph::SceneGraph& g, const WorldState& s);
/// Whether `object` is held or rests (transitively) on the held object.
bool carried(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object);

/// Height of `object` together with everything resting on it (what is carried along when it is
/// picked): the highest top in its subtree minus its own bottom. This is what must fit under a
/// destination's clearance.
double stack_height(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object);

/// The platform an object is (transitively) on that is owned by furniture, or none.
graph::PlatformId furniture_platform_of(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object);

}  // namespace mtg::episode
