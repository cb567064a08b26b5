#pragma once
// Paired comparison of two agents of a run, or of one agent in two runs, on the tasks both ran
// (docs/statistics.md): per level and over all levels, the difference in SR and IP with 95 %
// intervals, an exact McNemar test on success, a sign-flip permutation test on IP, Holm's
// correction across the agents compared, the smallest difference the run could detect, and the
// tasks whose outcome flipped.

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "orchestrator/run/marks.h"
#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator {

/// An episode a person excluded, with the reason given.
struct ExcludedRow {
  EpisodeRow row;
  std::string reason;
};

/// One side of a comparison: the scored episodes of `agent` in `run`.
struct CompareSide {
  std::string run;
  std::string agent;
  std::vector<EpisodeRow> rows;
  /// Episodes per repeat in the run's plan (its tasks × agents; run_plan.h lays episodes out
  /// repeat by repeat), so an episode's repeat is id / per_repeat; 0 when unknown, and then the
  /// k-th row of a task is repeat k.
  std::int64_t per_repeat = 0;
  /// The scored episodes of the run a person excluded (marks.h), with the reason given: a
  /// comparison says how many of each side it leaves out and why, and which unpaired episodes
  /// lost their partner to an exclusion on the other side.
  std::vector<ExcludedRow> excluded{};
};

/// Compares each `candidates[i]` with `baselines[i]` (B with A: differences are B - A). Episodes
/// pair when they ran the same task and are the same repeat. Rows not scored are left out. The
/// bootstrap and Monte Carlo draws are seeded by the agents and the level, not the runs' names,
/// so a renamed folder compares the same. Keys: comparisons[{a, b, pairs, unpaired_a,
/// unpaired_b, excluded_a, excluded_b ({episodes, reasons: {reason: n}}), unpaired_a_excluded_in_b,
/// unpaired_b_excluded_in_a (unpaired episodes whose partner a person excluded), levels: {"1"..., "all": {pairs, sr_a, sr_b, sr_diff, sr_diff_ci, only_a, only_b,
/// sr_p, sr_p_holm, sr_detectable, ip_a, ip_b, ip_diff, ip_diff_ci, ip_p, ip_p_holm, ip_detectable}},
/// regressions, improvements: [{task, level, episode_a, episode_b}]}], alpha.
/// @throws mtg::Error when the sides differ in number or a pair of sides shares no task.
nlohmann::json compare_sides(const std::vector<CompareSide>& baselines, const std::vector<CompareSide>& candidates);

/// A run's results for a comparison: its name and rows.
struct RunRows {
  std::string name;
  std::vector<EpisodeRow> rows;  ///< without the episodes a person excluded (marks.h)
  std::vector<ExcludedRow> excluded{};  ///< those, with their reasons
  /// What the run's task ids mean (provenance.h, task_set_identity); "" when unknown. Two runs on
  /// different task sets pair by id all the same, with a warning.
  std::string task_set;
  std::int64_t per_repeat = 0;  ///< as in CompareSide
};

/// What `mtg compare` and the viewer compare. With `b`: every agent of both runs (or `agent`
/// only), B against A. Without: every agent of `a` (or `agent`) against `baseline` (default: the
/// run's first agent, by episode order). @throws mtg::Error naming what does not fit (an agent
/// not in the run, --baseline with two runs, a run of one agent, nothing in common). Runs on
/// different task sets get "warning".
nlohmann::json compare_runs(const RunRows& a, const RunRows* b, const std::string& agent, const std::string& baseline);

/// A run's rows for a comparison from all its results and its people's marks (marks.h): the
/// excluded ones apart, with their reasons.
RunRows run_rows(std::string name, const std::vector<EpisodeRow>& all, const std::map<bus::EpisodeId, EpisodeMarks>& marks,
                 std::string task_set, std::int64_t per_repeat);

/// A run folder's rows for a comparison: results without the excluded episodes, the task set's
/// identity and the plan's layout. @throws mtg::Error naming the folder when it is not a run.
RunRows load_run_rows(const std::filesystem::path& dir, const std::string& name);

/// The comparison as text: a table per comparison and a plain verdict ("not significant").
std::string compare_text(const nlohmann::json& comparison);

}  // namespace mtg::orchestrator
