#pragma once
// A top-down map of the scene graph that a person can read: furniture outlines, platforms
// coloured by navigability, items, standing areas and standing points, and labels.

#include <filesystem>

#include "core/graph/scene_graph.h"

namespace mtg::graph {

struct TopdownOptions {
  double pixels_per_metre = 120.0;
};

/// Writes a PNG. @throws mtg::Error if the file cannot be written.
void write_topdown_png(const SceneGraph& graph, const std::filesystem::path& file,
                       const TopdownOptions& options = {});

}  // namespace mtg::graph
