#pragma once
// Mesh-level interpenetration tests between objects (FCL). Kept in its own unit: FCL's headers
// are among the slowest to compile.

#include <utility>
#include <vector>

#include "core/geom/triangles.h"

namespace mtg::graph {

/// Pairs (i, j), i < j, among `candidates` whose meshes interpenetrate by more than `tolerance`
/// metres (each mesh is shrunk by `tolerance` towards its centre first, so touching objects,
/// e.g. books side by side, do not count).
std::vector<std::pair<int, int>> interpenetrating_pairs(
    const std::vector<const geom::TriangleSoup*>& meshes,
    const std::vector<std::pair<int, int>>& candidates, double tolerance);

}  // namespace mtg::graph
