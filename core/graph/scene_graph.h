#pragma once
// The receptacle-aware scene graph (DESIGN.md §3): furniture on the ground, platforms of the
// furniture (top surfaces and interior layers), items settled on platforms, standing areas and
// navigability. Built once per scene by build_scene_graph() and then const; episodes keep their
// own WorldState (world_state.h).
//
// Frames: W world (Z-up); P a platform frame, origin at the centre of the platform's bounding box
// in its owner's heading, x = heading ("right"), y = heading + 90° ("front"), z = surface height.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <limits>
#include <string>
#include <map>
#include <set>
#include <vector>

#include "core/geom/polygon.h"
#include "core/graph/ids.h"
#include "core/util/id_vector.h"

namespace mtg::graph {

enum class ObjectKind {
  kFurniture,      // stands on the floor, or is fixed to the structure (wall-mounted cupboard);
                   // owns the platforms tasks send items to
  kItem,           // movable (DYNAMIC) and resting on a platform: pickable
  kFixed,          // scenery: STATIC objects and objects the scene profile excludes. Obstacles
                   // where they stand, may support items, never picked, never destinations
  kFloorCovering,  // flat on the floor (rugs, mats): part of the floor
  kUnsupported,    // a movable object that rests on nothing: reported, not in the tree
};
const char* to_string(ObjectKind kind);

/// The four sides of a platform, in the paper's order (rear, left, front, right).
enum class Side { kRear = 0, kLeft = 1, kFront = 2, kRight = 3 };
inline constexpr std::array<Side, 4> kSides = {Side::kRear, Side::kLeft, Side::kFront, Side::kRight};
const char* to_string(Side side);

struct GraphObject {
  std::string name;
  std::string template_name;
  std::string short_name;   // template without the dataset prefix ("name without instance id")
  std::string category;     // semantic class ("" if none)
  std::string noun;         // what a person calls it (scene profile; "" if the profile has none)
  std::string noun_plural;  // "" when the regular plural of `noun` reads right
  ObjectKind kind = ObjectKind::kUnsupported;
  std::string note;         // why it is scenery / unsupported, or how it was settled
  bool excluded = false;    // named by the scene profile (then it is scenery, kFixed)
  bool movable = false;     // DYNAMIC rigid and kept by the profile: furniture or item, never
                            // unsupported in a well-formed scene
  PlatformId parent;        // supporting platform; none: on the floor / fixed to the structure
  Eigen::Isometry3d X_WO = Eigen::Isometry3d::Identity();  // settled pose
  double bottom = 0.0;      // world z of the lowest point (settled)
  double top = 0.0;         // world z of the highest point (settled)
  double settle_dz = 0.0;   // vertical move applied by settling
  geom::Ring footprint;     // convex hull of the xy projection, world frame (settled)
  double heading = 0.0;     // yaw of its frame's x axis (furniture: canonical min-area rectangle)
  std::vector<PlatformId> platforms;  // platforms it owns, bottom-up

  bool pickable() const { return kind == ObjectKind::kItem; }
  double height() const { return top - bottom; }
};

struct SideInfo {
  geom::Ring strip_W;                       // the strip searched for standing cells (world)
  double standing_area = 0.0;               // m², floor where the robot can stand on this side
  geom::Point2 standing_point = geom::Point2::Zero();  // world xy of the chosen robot centre
  bool visible = false;                     // the surface can be seen from the standing point
  /// Where the robot can stand along the side, every 10 cm across it (world xy): in each
  /// 10 cm slice of the strip the valid centre nearest the owner's face. Views of part of a
  /// long platform stand in front of that part (render/view.h).
  std::vector<geom::Point2> stands;
  /// How many of the platform's objects the view from the standing point shows (at least 4 of 6
  /// sight lines to each reach it), as the graph found them: the arrival side is chosen by it.
  int objects_seen = 0;
  int sight_lines = 0;  // of the 6 lines to each object, those that pass nothing (ties of objects_seen)
  bool usable() const { return standing_area > 0.0 && visible; }
};

struct Platform {
  std::string name;          // "<owner>_platform_<index>"
  ObjectId owner;
  int index = 0;             // bottom-up rank within the owner
  double height = 0.0;       // world z of the supporting surface
  double clearance = std::numeric_limits<double>::infinity();  // free height above
  bool interior = false;     // covered by its own owner (shelf, drawer cavity)
  std::string source;        // "receptacle:<key>", "mesh", or "mesh:supports-item"
  Eigen::Isometry2d X_WP = Eigen::Isometry2d::Identity();
  geom::Region polygon_P;    // supporting area in P
  Eigen::AlignedBox2d box_P; // its bounding box in P (centred at the origin)
  std::array<SideInfo, 4> sides;
  bool destination = false;  // owned by furniture: a place tasks may send items to
  bool navigable = false;    // destination with a usable side
  int label = 0;             // the agent's number l<label>; 0 when not navigable
  std::vector<ObjectId> items;  // objects resting directly on it (items and fixed), in order

  geom::Region polygon_W() const;
  double area() const { return geom::area(polygon_P); }
  /// The usable side the robot arrives at (`l<N>`): the one whose view shows the most of the
  /// platform's objects, then the one with the most standing area (see standing.h).
  int default_side = -1;
};

/// The agent's key for navigable platform number `label`: "l<label>".
std::string navigation_key(int label);

struct SceneGraph {
  std::string scene;
  IdVector<ObjectId, GraphObject> objects;
  IdVector<PlatformId, Platform> platforms;
  std::vector<PlatformId> navigable;  // platforms by label: navigable[k-1] has label k
  std::vector<std::string> warnings;
  /// Words that cover other nouns (GraphOptions::noun_covers), from the profile.
  std::map<std::string, std::set<std::string>> noun_covers;

  /// Whether a person told `word` considers an object called `noun`: the same noun, or one the
  /// word covers ("cup" for a mug).
  bool called(const std::string& word, const std::string& noun) const;
  /// The words that cover `noun` (not the noun itself), in the profile's order.
  std::vector<std::string> words_covering(const std::string& noun) const;
  ObjectId find_object(const std::string& name) const;      // none if absent
  PlatformId find_platform(const std::string& name) const;  // none if absent
  /// Pickable objects on a platform in the agent's o-numbering: each direct child followed by
  /// its own descendants (the paper's order), as the graph found them.
  std::vector<ObjectId> pickable_on(PlatformId platform) const;
  /// The same order where `children_of(p)` lists what rests on platform p now (a world state's
  /// view, episode::pickable_on); `children_of` returns a const std::vector<ObjectId>&.
  template <class ChildrenOf>
  std::vector<ObjectId> pickable_on(PlatformId platform, const ChildrenOf& children_of) const;
};

template <class ChildrenOf>
std::vector<ObjectId> SceneGraph::pickable_on(PlatformId platform, const ChildrenOf& children_of) const {
  std::vector<ObjectId> out;
  const std::vector<ObjectId>& direct = children_of(platform);
  std::vector<ObjectId> stack(direct.rbegin(), direct.rend());
  while (!stack.empty()) {
    const ObjectId o = stack.back();
    stack.pop_back();
    const GraphObject& obj = objects[o];
    if (obj.pickable()) out.push_back(o);
    // What rests on this object's own platforms comes right after it.
    std::vector<ObjectId> above;
    for (const PlatformId p : obj.platforms) {
      const std::vector<ObjectId>& on = children_of(p);
      above.insert(above.end(), on.begin(), on.end());
    }
    stack.insert(stack.end(), above.rbegin(), above.rend());
  }
  return out;
}

}  // namespace mtg::graph
