#pragma once
// The report of a run: a Table-3-style table (SR and IP per level and per agent), the failure
// taxonomy, and the failure Sankey diagram (task level -> stage reached -> cause -> outcome) as a
// self-contained HTML/SVG page that opens offline, a PNG of the same, and JSON.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator {

/// Keys: episodes, scored, errors, sr, ip (percent / points, over scored episodes), by_level
/// ({"1": {episodes, sr, ip}, ...}), by_agent ({agent: {episodes, sr, ip, by_level}}), causes,
/// stages, tokens, cost_usd, sankey ({nodes: [{id, label, column, value}], links: [{source,
/// target, value}]}). No wall-clock figures: the same results give the same JSON.
nlohmann::json make_report(const std::vector<EpisodeRow>& rows, const std::string& run_id);

std::string report_html(const nlohmann::json& report);
/// @throws mtg::Error if the file cannot be written.
void write_report_png(const nlohmann::json& report, const std::filesystem::path& file);

/// Writes report.json, report.html and report.png into `run_dir` (or `html` if given).
nlohmann::json write_reports(const std::filesystem::path& run_dir, const std::string& html = "");

}  // namespace mtg::orchestrator
