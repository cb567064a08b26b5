#pragma once
// Where a held object can go on the current platform: the numbered targets the agent chooses
// from after `startplace`, and the exact position a choice resolves to. One source of truth for
// the observation text, the renderer's numbers, task generation and the judge.
//
// Empty platform: keys 1..9 are the 3x3 cells in the paper's order (1 rear, 2 rear-left, 3 left,
// 4 front-left, 5 front, 6 front-right, 7 right, 8 rear-right, 9 center), named from where the
// robot stands. Occupied platform: keys 1..K number the free-space regions of the objects on it
// (objects in platform order, each object's directions in that same order, relative to the
// robot), skipping regions smaller than min_region_size. Key 999 means "anywhere it fits".
//
// A target resolves to the position nearest its aim point (the cell's centre; the middle of the
// anchor's edge or its corner, so the object ends up next to the anchor; the platform's centre)
// where the object's footprint centre lies in the target region, the footprint inside the
// platform and clear of every other object (1 mm margin); of those positions, only ones at least
// kPlacementInset inside the region are used when there are any, so a placement never grazes an
// edge.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/episode/world_state.h"
#include "core/graph/free_space.h"
#include "core/util/memo_table.h"

namespace mtg::episode {

inline constexpr const char* kAnywhereKey = "999";
/// A target puts the footprint centre at least this far (m) inside its free region when the
/// region allows, so a placement never sits on the edge of the goal it was meant for (a
/// sub-millimetre difference must not change a verdict: docs/tasks.md, "Robust placements").
inline constexpr double kPlacementInset = 0.012;

struct PlaceTarget {
  enum class Kind { kGridCell, kObjectRegion, kAnywhere };
  std::string key;
  Kind kind = Kind::kAnywhere;
  int relative_dir = -1;   // as the robot names it (0..7, 8 centre); -1 for anywhere
  int platform_dir = -1;   // in the platform frame
  graph::ObjectId anchor;  // object of an object region
  geom::Region region_P;   // where the footprint centre must land (platform frame)
  /// region_P kPlacementInset smaller on every side; computed by resolve_target when absent
  /// (callers that resolve one target many times fill it once: with_insets()).
  std::optional<geom::Region> region_inset_P;
  geom::Point2 aim_P = geom::Point2::Zero();
};

struct PlacementMemo;

/// The target "anywhere on the platform" (kAnywhereKey): offered on every platform, always last.
PlaceTarget anywhere_target(const graph::Platform& platform);

/// Targets offered on `platform` for a robot standing at `side` (the same with or without `memo`).
std::vector<PlaceTarget> place_targets(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform,
                                       graph::Side side, double min_region_size, PlacementMemo* memo = nullptr);

/// The anchors of `targets` that have no number in `numbering` (scenery: a TV box, a blanket),
/// in the order the targets first name them. The placing view marks each with a letter of its own
/// (anchor_letter of its index) and the action space names it by that letter, so every object an
/// option names carries a mark in the picture (issue 53).
std::vector<graph::ObjectId> lettered_anchors(const std::vector<PlaceTarget>& targets,
                                              const std::vector<graph::ObjectId>& numbering);
/// "A" ... "Z", then "A2" ... "Z2", ...
std::string anchor_letter(std::size_t index);

/// Fills every target's region_inset_P (from `memo` when given).
void with_insets(std::vector<PlaceTarget>& targets, PlacementMemo* memo = nullptr);

/// The held object's footprint relative to its footprint centre, in the platform's axes.
geom::Ring held_footprint_P(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform);

/// Footprint-centre positions (platform frame) where the held object fits on `platform`, and
/// those at least kPlacementInset inside them.
struct FeasibleCentres {
  geom::Region all;
  geom::Region inset;
  bool empty() const { return all.empty(); }
};
FeasibleCentres held_feasible_centres(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform,
                                      PlacementMemo* memo = nullptr);

/// The world position of the held object's reference point if `target` can take it, using the
/// precomputed feasible centres (held_feasible_centres); nullopt when the region is too small.
std::optional<Eigen::Vector2d> resolve_target(const graph::SceneGraph& g, const WorldState& s,
                                              graph::PlatformId platform, const PlaceTarget& target,
                                              const FeasibleCentres& feasible_centres, PlacementMemo* memo = nullptr);

/// The placement geometry of one scene graph that callers asking the same questions many times
/// over keep (task generation: every Level 3 chain and Level 4 plan places items among nearly
/// the same neighbours; about four in five of its computations repeat one made before). Each
/// table is keyed by the exact bytes of its inputs, a platform by its id, so one memo serves one
/// scene graph; the functions above give the same bits with or without it.
struct PlacementTables {
  /// Regions kept at most, per kind: most are asked for once or twice (near where a step put
  /// something), a few again and again. On the three shipped apartments, 4,096 keeps all the
  /// gain of keeping every one and 16 MiB less at the peak (23,000 regions a scene).
  static constexpr std::size_t kRegionsKept = 4096;
  BoundedMemoTable<geom::Region> insets{kRegionsKept};  // a target region kPlacementInset smaller
  MemoTable<geom::Region> interiors;    // graph::placeable_interior: platform, item footprint
  MemoTable<std::array<graph::FreeRegion, 9>> cells;  // graph::grid_cells: platform
  BoundedMemoTable<geom::Region> clips{kRegionsKept};   // a rectangle clipped to a platform polygon: platform, corners
};

struct PlacementMemo {
  /// `whole_results`: keep whole held_feasible_centres results too. They repeat where many plans
  /// start from one state (Level 4: seven in ten), hardly where each state is new (enumeration,
  /// Level 3 chains), and each holds every obstacle in its key: there they would only take memory.
  /// `shared`: the tables of another memo of the same scene graph, to share (Levels 1-3 and
  /// Level 4 ask for nearly the same interiors); new ones when null.
  explicit PlacementMemo(bool keep_whole_results = false, std::shared_ptr<PlacementTables> shared = nullptr)
      : whole_results(keep_whole_results),
        tables(shared ? std::move(shared) : std::make_shared<PlacementTables>()) {}
  const bool whole_results;
  const std::shared_ptr<PlacementTables> tables;  // never null
  MemoTable<FeasibleCentres> feasible;  // held_feasible_centres: platform, obstacles, item footprint
  /// With whole_results, the targets of the last placing state asked about (a plan that chooses
  /// a target asks for them, then the step that places asks again), not every state's: they
  /// are large and seldom asked for a third time.
  MemoSlot<std::vector<PlaceTarget>> last_targets;
};

/// Short display name of an object for the agent: template without instance id, spaced
/// ("kitchen utensil 09"), so identical objects read the same (the Level 2 ambiguity).
std::string display_name(const graph::GraphObject& o);

/// How an object reads in lists for agents told names: what a person calls it and its model
/// ("spice jar (kitchen utensil 03)"), so a task's noun and the list's words agree; the display
/// name alone when the scene profile gives no other noun.
std::string listed_name(const graph::GraphObject& o);

}  // namespace mtg::episode
