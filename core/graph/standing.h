#pragma once
// Where the robot can stand, and what it can see from there (DESIGN.md §3 "Standing areas").
//
// Furniture footprints (the xy projection of every triangle) are rasterised once per scene at
// 1 cm; a cell is a valid robot centre when the robot square around it holds no furniture.
// A platform side's standing area is the set of valid centres within `standing_depth` of its
// owner's outer face, across the platform's extent; the standing point is the valid centre
// nearest to the middle of that strip. Walls are unknown (no stage mesh), so only furniture
// blocks the robot.

#include <opencv2/core.hpp>
#include <vector>

#include "core/geom/polygon.h"
#include "core/geom/triangles.h"
#include "core/graph/options.h"
#include "core/graph/scene_graph.h"

namespace mtg::graph {

class FloorRaster {
 public:
  /// Rasterises the footprints of `obstacles` over their bounds plus a 1 m margin; `steppable[i]`
  /// says obstacle i is light furniture a person steps around (GraphOptions::steppable_max_area).
  FloorRaster(const std::vector<const geom::TriangleSoup*>& obstacles, const std::vector<bool>& steppable,
              const GraphOptions& options);

  double resolution() const { return resolution_; }
  /// Cell centre of (row, col) in world xy.
  geom::Point2 cell_centre(int row, int col) const;
  /// Row/column of the cell holding p (may be outside the raster).
  cv::Point2i cell_of(const geom::Point2& p) const;
  const cv::Mat& robot_free() const { return robot_free_; }    // CV_8U, 1 = clear of everything
  const cv::Mat& robot_room() const { return robot_room_; }    // CV_8U, 1 = clear but for steppable furniture

 private:
  double resolution_;
  geom::Point2 origin_;  // world xy of the corner of cell (0, 0)
  cv::Mat robot_free_;
  cv::Mat robot_room_;
};

/// Fills `platform.sides` (standing area, standing point, the stands along the side,
/// visibility). The standing area counts the room a person has (steppable furniture does not
/// take it); the standing point is clear of everything where the strip allows. `owner_footprint`
/// is the owner's convex footprint (world); `owner_heading` its heading; `owner_soup` its
/// triangles (occluders of the visibility rays).
void evaluate_sides(Platform& platform, const geom::Ring& owner_footprint, double owner_heading,
                    const geom::TriangleSoup& owner_soup, const FloorRaster& raster,
                    const GraphOptions& options);

/// The arrival side: the usable side whose view shows the most objects (SideInfo::objects_seen),
/// then the most clear sight lines to them, then the most standing area; -1 when none is usable.
int arrival_side(const Platform& platform);

/// The eye height of the views of a platform (render/view.h): above the tallest thing on it,
/// looking down on the surface, but under the layer above a platform with finite clearance, so
/// the robot looks into a cabinet rather than at its top.
double eye_height(const Platform& platform, double platform_height, double tallest_top);

}  // namespace mtg::graph
