#pragma once
// The report of a run: a Table-3-style table (SR and IP per level and per agent), the failure
// taxonomy, and the failure Sankey diagram (task level -> stage reached -> cause -> outcome) as a
// self-contained HTML/SVG page that opens offline, a PNG of the same, and JSON.

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "orchestrator/run/marks.h"
#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator {

/// Keys: episodes, scored, errors, sr, ip (percent / points, over scored episodes), sr_ci and
/// ip_ci (95 % intervals: Wilson; seeded bootstrap), by_level ({"1": {episodes, sr, sr_ci, ip,
/// ip_ci}, ...}), by_agent ({agent: {episodes, sr, sr_ci, ip, ip_ci, by_level, paper_avg: {levels,
/// sr, sr_ci, ip, ip_ci} or null without Levels 1-3, repeats: {tasks, episodes_per_task: [fewest,
/// most], pass_at_k: [k = 1...], pass_hat_k, k_of_n: {"c/n": tasks}} only where a task ran more
/// than once}}), causes,
/// stages, tokens, cost_usd, sankey ({nodes: [{id, label, column, value}], links: [{source,
/// target, value}]}). No wall-clock figures: the same results give the same JSON.
/// With `marks` (a person's flags, tags and exclusions, orchestrator/run/marks.h): excluded
/// episodes leave every figure, and the report adds "excluded" ([{episode, reason}]) and "marks"
/// ({"<episode>": {flagged, tags, excluded, reason}}); a run without marks reports as before.
nlohmann::json make_report(const std::vector<EpisodeRow>& rows, const std::string& run_id,
                           const std::map<bus::EpisodeId, EpisodeMarks>* marks = nullptr);

std::string report_html(const nlohmann::json& report);

/// "50.0 [40.2, 59.8]": figures[key] with figures[key + "_ci"] when present.
std::string with_interval(const nlohmann::json& figures, const std::string& key);
/// The same for a table cell: the interval on a second, smaller line.
std::string with_interval_html(const nlohmann::json& figures, const std::string& key);
/// One agent's repeats (its report's "repeats") in a line: pass@k, pass^k and tasks by successes.
std::string repeats_text(const std::string& agent, const nlohmann::json& repeats);
/// The report's repeats section (HTML), or "" when no task ran more than once.
std::string repeats_html(const nlohmann::json& report);
/// "Avg (L1–3)", or over the paper's levels the run has ("Avg (L1–2)"); "" with none of them.
std::string paper_average_label(const nlohmann::json& report);
/// The same for a list of levels (a paper_avg's "levels").
std::string average_label(const nlohmann::json& levels);
/// @throws mtg::Error if the file cannot be written.
void write_report_png(const nlohmann::json& report, const std::filesystem::path& file);

/// Writes report.json, report.html and report.png into `run_dir` (or `html` if given), with the
/// run's marks applied.
nlohmann::json write_reports(const std::filesystem::path& run_dir, const std::string& html = "");

}  // namespace mtg::orchestrator
