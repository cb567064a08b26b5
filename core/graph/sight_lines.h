#pragma once
// Which objects a person standing at a platform's side sees, from sight lines in the world's
// triangles: the scene graph's estimate of what a side's view shows, which chooses the side the
// robot arrives at (standing.h, arrival_side). The views the agent gets are then drawn, and what
// tasks may name is decided on them (render/visibility.h); this only ranks the sides.

#include <Eigen/Geometry>
#include <vector>

#include "core/geom/triangles.h"
#include "core/graph/ids.h"

namespace mtg::graph {

/// An object looked for, by its world box.
struct SightTarget {
  ObjectId object;
  Eigen::AlignedBox3d box;
};

/// A thing that may stand in the way.
struct Occluder {
  ObjectId object;
  const geom::TriangleSoup* soup = nullptr;
};

struct Seen {
  int objects = 0;  // targets seen: at least 4 of their 6 sight lines clear
  int lines = 0;    // clear sight lines in all (ranks views that see the same objects)
};

/// What a person with eyes at `eye` sees of `targets`: the lines to six points inside each
/// target's box (two on its vertical axis, four around it at half height) that pass no
/// occluder's triangle; a target never hides itself.
Seen count_seen(const Eigen::Vector3d& eye, const std::vector<SightTarget>& targets,
                const std::vector<Occluder>& occluders);

/// How many of the lines from `eye` to `points` pass no occluder's triangle.
int clear_lines(const Eigen::Vector3d& eye, const std::vector<Eigen::Vector3d>& points,
                const std::vector<Occluder>& occluders);

}  // namespace mtg::graph
