#pragma once
// Building the scene graph from a loaded scene: classify objects, find platforms, settle items
// onto them, measure standing areas and visibility, number the navigable platforms.

#include "core/graph/options.h"
#include "core/graph/scene_graph.h"
#include "core/scene/scene.h"

namespace mtg::graph {

struct BuildTimings {  // telemetry, milliseconds
  double geometry = 0, platforms = 0, settle = 0, clearance = 0, overlap = 0, standing = 0, total = 0;
};

/// Never throws for bad geometry: objects that cannot be handled get a kind that keeps them out
/// of the tree (kUnsupported) and a warning naming them; the rest of the graph still builds.
SceneGraph build_scene_graph(const scene::Scene& scene, const GraphOptions& options,
                             BuildTimings* timings = nullptr);

}  // namespace mtg::graph
