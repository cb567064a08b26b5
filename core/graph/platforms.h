#pragma once
// Platforms of one object: the horizontal surfaces things can stand on.
//
// With declared receptacles (receptacle_aabb entries), each receptacle selects the physical
// surface it was annotated on: the highest upward mesh surface overlapping the box footprint
// whose height lies within [box bottom - 10 cm, box bottom + 3 cm] (the boxes are sampling
// volumes that start at or slightly above the surface). Receptacles on the same surface give
// one platform; receptacles on doors/drawers (closed) and receptacles without a surface are
// dropped with a warning. Surfaces no receptacle selects stay in reserve: they become platforms
// only if an item in the scene actually rests on one.
//
// Without declared receptacles, every upward surface that passes the size filters is a
// platform: area >= min_platform_area, >= relative_platform_area x the largest, narrow strips
// and surfaces above max_platform_height excluded.

#include <string>
#include <vector>

#include "core/graph/object_geometry.h"
#include "core/graph/options.h"
#include "core/graph/surfaces.h"
#include "core/scene/scene.h"

namespace mtg::graph {

struct PlatformCandidate {
  Surface surface;
  std::string source;    // "receptacle:<key>[,<key>]" or "mesh"
  bool active = true;    // false: kept in reserve (see above)
};

/// Surface detection as the graph options ask for it (platforms and the surfaces above them).
SurfaceOptions surface_options(const GraphOptions& options);

/// Candidates of `object` standing at `X_WO` (its settled pose) with world geometry
/// `geometry`, lowest first. Problems (receptacle without surface, zero-area receptacle) are
/// appended to `warnings`.
std::vector<PlatformCandidate> platform_candidates(const scene::ObjectInstance& object,
                                                   const Eigen::Isometry3d& X_WO,
                                                   const ObjectGeometry& geometry,
                                                   const GraphOptions& options,
                                                   std::vector<std::string>& warnings);

/// Width of a region's narrowest side in its own minimum-area rectangle.
double min_width(const geom::Region& region);

}  // namespace mtg::graph
