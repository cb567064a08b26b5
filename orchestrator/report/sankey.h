#pragma once
// The failure Sankey diagram: every episode is one unit of flow through four columns (task level
// -> stage reached -> cause or "success" -> outcome). One layout serves the SVG (report.html) and
// the PNG.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mtg::orchestrator {

struct SankeyFlow {
  std::string level, stage, cause, outcome;
};

/// {"nodes": [{"id", "label", "column", "value"}], "links": [{"source", "target", "value"}]},
/// in a deterministic order.
nlohmann::json sankey_graph(const std::vector<SankeyFlow>& flows);

std::string sankey_svg(const nlohmann::json& graph, int width, int height);
/// The size report.html, `mtg view` and `mtg export` draw it at.
inline constexpr int kSankeyWidth = 1000, kSankeyHeight = 520;
void sankey_png(const nlohmann::json& graph, const std::string& title, const std::filesystem::path& file, int width,
                int height);

}  // namespace mtg::orchestrator
