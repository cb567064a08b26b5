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
  /// Rasterises the footprints of `obstacles` over their bounds plus a 1 m margin.
  FloorRaster(const std::vector<const geom::TriangleSoup*>& obstacles, const GraphOptions& options);

  double resolution() const { return resolution_; }
  /// Cell centre of (row, col) in world xy.
  geom::Point2 cell_centre(int row, int col) const;
  /// Row/column of the cell holding p (may be outside the raster).
  cv::Point2i cell_of(const geom::Point2& p) const;
  const cv::Mat& robot_free() const { return robot_free_; }    // CV_8U, 1 = valid centre

 private:
  double resolution_;
  geom::Point2 origin_;  // world xy of the corner of cell (0, 0)
  cv::Mat robot_free_;
};

/// Fills `platform.sides` (standing area, standing point, visibility) and `default_side`.
/// `owner_footprint` is the owner's convex footprint (world); `owner_heading` its heading;
/// `owner_soup` its triangles (occluders of the visibility rays).
void evaluate_sides(Platform& platform, const geom::Ring& owner_footprint, double owner_heading,
                    const geom::TriangleSoup& owner_soup, const FloorRaster& raster,
                    const GraphOptions& options);

}  // namespace mtg::graph
