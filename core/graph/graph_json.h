#pragma once
// graph.json: the scene graph as a stable, diff-friendly JSON document (format in docs/graph.md).
// Lengths are rounded to 0.1 mm and areas to 0.1 cm², so the same scene always gives the same
// bytes and golden files stay readable.

#include <nlohmann/json.hpp>

#include "core/graph/options.h"
#include "core/graph/scene_graph.h"

namespace mtg::graph {

inline constexpr const char* kGraphFormat = "mtg-scene-graph/1";

nlohmann::json graph_to_json(const SceneGraph& graph, const GraphOptions& options);

/// Counts: objects by kind, platforms, destinations, navigable platforms, pickable items on
/// navigable platforms.
nlohmann::json graph_summary(const SceneGraph& graph);

}  // namespace mtg::graph
