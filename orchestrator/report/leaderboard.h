#pragma once
// A leaderboard over runs (docs/statistics.md, "Leaderboard"): entrants (an agent of a run)
// ranked by SR, with what the paired tests can and cannot say about the order. Two entrants are
// told apart only by an exact McNemar test on the (task, repeat) pairs both ran, Holm-adjusted
// over every pair of the board; entrants no test separates are shown as tied, and each entrant
// gets the range of ranks the tests leave open. Runs on different suites are never ranked
// together: each suite is its own board.

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator {

/// One run on a leaderboard.
struct LeaderboardRun {
  std::string name;
  std::vector<EpisodeRow> rows;  ///< without the episodes a person excluded (as load_run_rows gives)
  std::string suite;             ///< suite_identity of its plan's provenance (with its look-alike
                                 ///< aid where not "both"); boards group by it
  std::int64_t per_repeat = 0;   ///< as in CompareSide: episodes per repeat, 0 when unknown
};

/// What a run's results are a benchmark of, from its plan's provenance: the suite's id
/// (provenance["suite"]["id"]), else "task set " + task_set_identity, else "unknown".
std::string suite_identity(const nlohmann::json& provenance);

/// A run folder's rows and suite, named by its folder; a run whose plan gives look-alikes by
/// words or images alone (`lookalike_aid`) is of "<suite>, look-alike aid words|image". @throws mtg::Error naming the folder when
/// it is not a run or its plan cannot be read.
LeaderboardRun load_leaderboard_run(const std::filesystem::path& dir);

/// Keys: boards[{suite, runs, entrants[{rank_best, rank_worst, label, run, agent, episodes, sr,
/// sr_ci, ip, ip_ci, groups: ["a", ...]}], pairs[{a, b, pairs, only_a, only_b, p, p_holm,
/// significant, note?}], groups[[label, ...]], alpha, note?}]. Entrants in SR order (ties: IP,
/// then label); pairs in that order too (a ranked above b). Figures and intervals are the
/// report's (make_report), so a board and a run's report print the same numbers.
/// @throws mtg::Error when two runs share a name (entrants would be ambiguous).
nlohmann::json make_leaderboard(const std::vector<LeaderboardRun>& runs);

/// A table per board, then a line per tied group and the board's notes.
std::string leaderboard_text(const nlohmann::json& leaderboard);

/// A Markdown table per board (for the export and result cards).
std::string leaderboard_markdown(const nlohmann::json& leaderboard);

}  // namespace mtg::orchestrator
