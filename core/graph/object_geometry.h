#pragma once
// World-space geometry of one scene instance, as the scene graph sees it.

#include "core/geom/polygon.h"
#include "core/geom/triangles.h"
#include "core/scene/scene.h"

namespace mtg::graph {

struct ObjectGeometry {
  geom::TriangleSoup soup;   // world frame, fixed parts only (doors and drawers left out)
  double bottom = 0.0;       // world z
  double top = 0.0;
  geom::Ring footprint;      // convex hull of the xy projection
  bool has_geometry() const { return !soup.empty(); }
};

/// Triangles of the instance's render meshes (its collision mesh where the render mesh is
/// missing, then its URDF boxes) in the world frame. Links on non-fixed joints (doors, drawers)
/// are left out: articulated furniture is treated as closed, with interiors reachable as the
/// paper treats them (its release drops those links too).
ObjectGeometry object_geometry(const scene::ObjectInstance& object);

/// The same geometry moved by a world translation (settling, placing).
void translate(ObjectGeometry& g, const Eigen::Vector3d& t);

}  // namespace mtg::graph
