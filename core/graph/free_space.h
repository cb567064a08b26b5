#pragma once
// Free space on a platform (DESIGN.md §3 "Free space"): around each object the eight
// directional regions, extended until they meet another object and clipped to the platform;
// an empty platform's 3x3 grid; and the exact set of positions where an item fits.
// Everything here is in the platform frame P (x = right, y = front of the platform).

#include <array>
#include <functional>
#include <vector>

#include "core/geom/polygon.h"
#include "core/graph/scene_graph.h"

namespace mtg::graph {

/// Directions in the paper's order; 8 is the centre (grid only).
inline constexpr int kNumDirections = 8;
inline constexpr int kCentre = 8;
const char* direction_name(int dir);  // "rear", "rear-left", ..., "rear-right", "center"

/// The platform-frame direction that an agent standing at `side` calls `relative`: the paper's
/// (d + s) mod 8, so "front" is always the part farthest from the agent. The centre maps to
/// itself.
int platform_direction(int relative, Side side);
/// Inverse of platform_direction.
int relative_direction(int platform_dir, Side side);
/// Which way a platform-frame direction points: x -1 left, +1 right; y -1 rear, +1 front;
/// (0, 0) for the centre. One table for every use of the direction numbering.
Eigen::Vector2i direction_step(int dir);

/// An object on the platform, seen as an obstacle in P.
struct Obstacle {
  ObjectId object;
  geom::Ring hull_P;          // convex footprint in P
  Eigen::AlignedBox2d box_P;  // its bounding box in P
};

/// Obstacles for `objects` given their world footprints.
std::vector<Obstacle> make_obstacles(const Platform& platform, const std::vector<ObjectId>& objects,
                                     const std::vector<geom::Ring>& footprints_W);

struct FreeRegion {
  ObjectId object;              // anchor object (none for grid cells)
  int dir = 0;                  // platform-frame direction 0..7 (kCentre for the grid centre)
  Eigen::AlignedBox2d rect_P;   // the region before clipping to the platform polygon
  geom::Region region_P;        // clipped to the platform polygon (may be empty)
  bool numbered = false;        // large enough (min_size both ways) to be offered to the agent
};

/// The 8 regions of every obstacle, in obstacle order then direction order. Side regions
/// extend from the object's edge to the nearest obstacle in that direction (or the platform
/// edge); corner regions are the largest rectangle anchored at the object's corner that holds
/// no obstacle.
/// The part of rectangle `rect` inside the platform's polygon.
geom::Region clip_to_polygon(const Platform& platform, const Eigen::AlignedBox2d& rect);

/// `clip`, when given, computes clip_to_polygon for a platform that does not fill its box, for
/// callers that remember the results: a region depends on nearby obstacles only, so it repeats
/// from state to state.
using RectClip = std::function<geom::Region(const Eigen::AlignedBox2d& rect)>;
std::vector<FreeRegion> object_regions(const Platform& platform, const std::vector<Obstacle>& obstacles,
                                       double min_size, const RectClip& clip = {});

/// Rectangle of grid cell `dir` (0..7, kCentre) of the platform's bounding box, in P.
Eigen::AlignedBox2d grid_cell_rect(const Platform& platform, int dir);

/// The 3x3 grid of the platform's bounding box, indexed by platform-frame direction (0..7) and
/// kCentre, each clipped to the polygon.
std::array<FreeRegion, 9> grid_cells(const Platform& platform);

/// Positions (of the item's reference point) where an item whose footprint is `item_hull`
/// (convex, relative to its reference point, in P axes) lies inside the platform polygon and
/// overlaps no obstacle.
geom::Region feasible_positions(const Platform& platform, const std::vector<Obstacle>& obstacles,
                                const geom::Ring& item_hull);
/// feasible_positions in two parts, for callers that keep the first: where the item lies inside
/// the platform polygon, then the part of `inside` where it also overlaps no obstacle.
geom::Region placeable_interior(const Platform& platform, const geom::Ring& item_hull);
geom::Region clear_of(const geom::Region& inside, const std::vector<Obstacle>& obstacles, const geom::Ring& item_hull);

/// a ⊕ b for convex rings (the hull of pairwise sums).
geom::Ring minkowski_convex(const geom::Ring& a, const geom::Ring& b);

}  // namespace mtg::graph
