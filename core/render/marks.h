#pragma once
// What an annotated image numbers, in world coordinates. The numbers come from the same
// functions that build the agent's action space (episode::pickable_on for o<N>,
// episode::place_targets for the placement keys, SceneGraph::navigable for l<N>), so an image
// can never disagree with the observation text.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/episode/placement.h"
#include "core/episode/world_state.h"

namespace mtg::render {

/// A pickable item: key o<number>, marked at the centre of its top.
struct ItemMark {
  int number = 0;
  graph::ObjectId object;
  Eigen::Vector3d anchor_W = Eigen::Vector3d::Zero();
};

/// A placement target (free-space region or 3x3 cell): key <number>, drawn on the surface.
struct RegionMark {
  int number = 0;
  std::vector<std::vector<Eigen::Vector3d>> rings_W;  // outer rings and holes, on the surface
  Eigen::Vector3d label_W = Eigen::Vector3d::Zero();  // a point inside the region
};

/// A navigable platform on the overview: key l<number>.
struct LabelMark {
  std::string text;
  Eigen::Vector3d anchor_W = Eigen::Vector3d::Zero();
};

struct Marks {
  std::vector<ItemMark> items;
  std::vector<RegionMark> regions;
  std::vector<LabelMark> labels;
  /// Placing views: the scenery the free spaces are named after, lettered as the action space
  /// names them (episode::lettered_anchors): "free space 32: rear-right of the TV box marked A".
  std::vector<LabelMark> fixtures;
  bool empty() const { return items.empty() && regions.empty() && labels.empty() && fixtures.empty(); }
};

/// The items the agent may pick on `platform`, numbered as its o<N> keys.
std::vector<ItemMark> item_marks(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform);

/// The placement targets offered on `platform` to a robot at `side` (not "anywhere").
std::vector<RegionMark> target_marks(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                     graph::Side side, double min_region_size);

/// The same for `targets`, place_targets' answer for the platform in `s`.
std::vector<RegionMark> target_marks(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                     const std::vector<episode::PlaceTarget>& targets);

/// The lettered anchors of `targets` (place_targets' answer for the platform in `s`), each at the
/// centre of its top.
std::vector<LabelMark> fixture_marks(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                     const std::vector<episode::PlaceTarget>& targets);

/// Every navigable platform with its l<N> key, at the centre of its surface.
std::vector<LabelMark> platform_labels(const graph::SceneGraph& g, const episode::WorldState& s);

}  // namespace mtg::render
