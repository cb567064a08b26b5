#pragma once
// Horizontal surfaces of a mesh: faces whose normal lies within a given angle of +z (or -z for
// ceilings), grouped by height, merged into polygons and split into connected pieces.

#include <vector>

#include "core/geom/polygon.h"
#include "core/geom/triangles.h"

namespace mtg::graph {

struct Surface {
  double height = 0.0;   // area-weighted mean height of its faces, world z
  geom::Region region;   // xy, world frame
  double area = 0.0;     // m²
};

struct SurfaceOptions {
  double max_angle_deg = 20.0;     // face normal within this angle of the direction
  double height_tolerance = 0.01;  // faces whose heights chain within this form one level
  double min_area = 0.0025;        // pieces smaller than this are dropped
};

/// Upward (facing +z) or downward (facing -z) surfaces, sorted by height then area.
/// Cracks narrower than 1 mm between coplanar faces are closed.
std::vector<Surface> detect_surfaces(const geom::TriangleSoup& soup, bool upward,
                                     const SurfaceOptions& options);

}  // namespace mtg::graph
