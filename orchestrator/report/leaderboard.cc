#include "orchestrator/report/leaderboard.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "core/stats/paired.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "orchestrator/report/compare.h"
#include "orchestrator/report/report.h"
#include "orchestrator/run/provenance.h"

namespace mtg::orchestrator {
namespace {

constexpr double kAlpha = 0.05;

struct Entrant {
  std::string run, agent, label;
  std::int64_t episodes = 0, successes = 0;  // scored: what SR is a rate of
  double ip_sum = 0.0;
  nlohmann::json figures;  // the report's {episodes, sr, sr_ci, ip, ip_ci}
  CompareSide side;        // the agent's rows only: each pair copies its sides
};

// Higher SR first. Rates are compared as exact fractions, so two entrants a rounding apart are
// not put in the wrong order; then higher IP, then the label, so the order never depends on the
// order the runs were given in.
bool ranks_above(const Entrant& x, const Entrant& y) {
  const std::int64_t lhs = x.successes * y.episodes, rhs = y.successes * x.episodes;
  if (lhs != rhs) return lhs > rhs;
  const double ip_x = x.ip_sum / static_cast<double>(x.episodes), ip_y = y.ip_sum / static_cast<double>(y.episodes);
  if (ip_x != ip_y) return ip_x > ip_y;
  return x.label < y.label;
}

// The agents of a run in the order they first ran (the run's own order), with their scored tallies.
std::vector<Entrant> entrants_of(const LeaderboardRun& run, bool several_runs, std::vector<std::string>& notes) {
  const nlohmann::json report = make_report(run.rows, run.name);
  std::vector<std::string> agents;
  for (const EpisodeRow& r : run.rows) {
    if (std::find(agents.begin(), agents.end(), r.agent) == agents.end()) agents.push_back(r.agent);
  }
  std::vector<Entrant> out;
  for (const std::string& agent : agents) {
    if (!report["by_agent"].contains(agent)) {
      notes.push_back(agent + " of " + run.name + ": no scored episode, not ranked");
      continue;
    }
    Entrant e;
    e.run = run.name;
    e.agent = agent;
    e.label = several_runs ? agent + " (" + run.name + ")" : agent;
    const nlohmann::json& a = report["by_agent"][agent];
    for (const char* key : {"episodes", "sr", "sr_ci", "ip", "ip_ci"}) e.figures[key] = a[key];
    e.side = {run.name, agent, {}, run.per_repeat};
    for (const EpisodeRow& r : run.rows) {
      if (r.agent != agent) continue;
      e.side.rows.push_back(r);
      if (r.status != "scored") continue;
      ++e.episodes;
      e.successes += r.success ? 1 : 0;
      e.ip_sum += r.ip;
    }
    out.push_back(std::move(e));
  }
  return out;
}

// One pair's McNemar test on the (task, repeat) pairs both ran, by compare_sides so that a board
// pairs episodes exactly as `mtg compare` does.
nlohmann::json pair_json(const Entrant& a, const Entrant& b) {
  nlohmann::json p = {{"a", a.label}, {"b", b.label}};
  try {
    const nlohmann::json c = compare_sides({a.side}, {b.side});
    const nlohmann::json& all = c["comparisons"][0]["levels"]["all"];
    p["pairs"] = all["pairs"];
    p["only_a"] = all["only_a"];
    p["only_b"] = all["only_b"];
    p["p"] = all["sr_p"];
  } catch (const Error&) {
    // compare_sides refuses sides that share no (task, repeat): no test was made, so nothing
    // separates the two, and the pair stays out of Holm's family (a test never made is not a
    // hypothesis to correct for).
    p["pairs"] = 0;
    p["only_a"] = 0;
    p["only_b"] = 0;
    p["p"] = 1.0;
    p["note"] = "no task ran on both: not tested";
  }
  return p;
}

// "a", ..., "z", "aa", "ab", ...: a letter per group, as in a compact letter display.
std::string group_letter(std::size_t k) {
  std::string s;
  for (std::size_t n = k + 1; n > 0; n = (n - 1) / 26) s.insert(s.begin(), static_cast<char>('a' + (n - 1) % 26));
  return s;
}

// The maximal intervals [i, j] of the ranked list inside which no pair is significant. The end
// reachable from i never falls as i grows, so an interval is maximal exactly when its end passes
// the end reached from the previous start.
std::vector<std::pair<std::size_t, std::size_t>> tied_intervals(const std::vector<std::vector<bool>>& significant) {
  const std::size_t n = significant.size();
  std::vector<std::pair<std::size_t, std::size_t>> out;
  std::size_t previous_end = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t end = i;
    while (end + 1 < n) {
      bool clean = true;
      for (std::size_t k = i; k <= end && clean; ++k) clean = !significant[k][end + 1];
      if (!clean) break;
      ++end;
    }
    if (i == 0 || end > previous_end) out.emplace_back(i, end);
    previous_end = end;
  }
  return out;
}

nlohmann::json board_json(const std::string& suite, const std::vector<const LeaderboardRun*>& runs) {
  std::vector<std::string> notes;
  std::vector<Entrant> entrants;
  nlohmann::json run_names = nlohmann::json::array();
  for (const LeaderboardRun* run : runs) {
    run_names.push_back(run->name);
    for (Entrant& e : entrants_of(*run, runs.size() > 1, notes)) entrants.push_back(std::move(e));
  }
  std::sort(entrants.begin(), entrants.end(), ranks_above);
  const std::size_t n = entrants.size();

  nlohmann::json pairs = nlohmann::json::array();
  std::vector<std::pair<std::size_t, std::size_t>> who;  // per pair: (i, j), i ranked above j
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      pairs.push_back(pair_json(entrants[i], entrants[j]));
      who.emplace_back(i, j);
    }
  }
  std::vector<double> tested_p;
  std::vector<std::size_t> tested;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    if (pairs[k].contains("note")) continue;
    tested.push_back(k);
    tested_p.push_back(pairs[k]["p"].get<double>());
  }
  const std::vector<double> adjusted = stats::holm_adjusted(tested_p);
  for (auto& p : pairs) p["p_holm"] = 1.0;
  for (std::size_t t = 0; t < tested.size(); ++t) pairs[tested[t]]["p_holm"] = adjusted[t];

  // better[x][y]: x is significantly better than y, in the direction of the discordant pairs
  // (a significant McNemar test never has as many on each side).
  std::vector<std::vector<bool>> significant(n, std::vector<bool>(n, false)), better = significant;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    nlohmann::json& p = pairs[k];
    p["significant"] = p["p_holm"].get<double>() < kAlpha;
    if (!p["significant"].get<bool>()) continue;
    const auto [i, j] = who[k];
    significant[i][j] = significant[j][i] = true;
    if (p["only_a"].get<std::int64_t>() > p["only_b"].get<std::int64_t>()) {
      better[i][j] = true;
    } else {
      better[j][i] = true;
    }
  }

  const auto intervals = tied_intervals(significant);
  std::vector<nlohmann::json> letters(n, nlohmann::json::array());
  nlohmann::json groups = nlohmann::json::array();
  for (std::size_t g = 0; g < intervals.size(); ++g) {
    nlohmann::json members = nlohmann::json::array();
    for (std::size_t i = intervals[g].first; i <= intervals[g].second; ++i) {
      members.push_back(entrants[i].label);
      letters[i].push_back(group_letter(g));
    }
    groups.push_back(members);
  }

  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i) {
    std::int64_t above = 0, below = 0;
    for (std::size_t j = 0; j < n; ++j) {
      above += better[j][i] ? 1 : 0;
      below += better[i][j] ? 1 : 0;
    }
    const Entrant& e = entrants[i];
    nlohmann::json row = {{"rank_best", 1 + above},
                          {"rank_worst", static_cast<std::int64_t>(n) - below},
                          {"label", e.label},
                          {"run", e.run},
                          {"agent", e.agent}};
    for (const auto& [key, value] : e.figures.items()) row[key] = value;
    row["groups"] = letters[i];
    list.push_back(std::move(row));
  }
  if (suite == "unknown") {
    notes.push_back("these runs' plans name neither a suite nor a task set (planned before provenance): "
                    "nothing shows they ran the same tasks");
  }
  return {{"suite", suite}, {"runs", run_names}, {"entrants", list}, {"pairs", pairs},
          {"groups", groups}, {"alpha", kAlpha}, {"notes", notes}};
}

// Characters, not bytes: a rank range holds a three-byte dash.
std::string padded(const std::string& s, std::size_t width) {
  const auto chars = static_cast<std::size_t>(std::count_if(s.begin(), s.end(), [](char c) { return (c & 0xC0) != 0x80; }));
  return s + std::string(width > chars ? width - chars : 1, ' ');
}

std::string rank_text(const nlohmann::json& e) {
  const auto best = e["rank_best"].get<std::int64_t>(), worst = e["rank_worst"].get<std::int64_t>();
  return best == worst ? std::to_string(best) : std::to_string(best) + "–" + std::to_string(worst);
}

std::string joined(const nlohmann::json& strings, const std::string& separator) {
  std::string out;
  for (const auto& s : strings) out += (out.empty() ? "" : separator) + s.get<std::string>();
  return out;
}

std::string percent_text(double alpha) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%g %%", 100.0 * alpha);
  return buf;
}

std::string tied_line(const nlohmann::json& board, const nlohmann::json& group) {
  return "tied (no paired test separates them, Holm " + percent_text(board["alpha"].get<double>()) +
         "): " + joined(group, ", ");
}

std::size_t tested_pairs(const nlohmann::json& board) {
  return static_cast<std::size_t>(std::count_if(board["pairs"].begin(), board["pairs"].end(),
                                                [](const nlohmann::json& p) { return !p.contains("note"); }));
}

std::string markdown_cell(const std::string& s) {
  std::string out;
  for (const char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

}  // namespace

std::string suite_identity(const nlohmann::json& provenance) {
  if (provenance.is_object()) {
    const auto suite = provenance.find("suite");
    if (suite != provenance.end() && suite->is_object()) {
      const auto id = suite->find("id");
      if (id != suite->end() && id->is_string() && !id->get<std::string>().empty()) return id->get<std::string>();
    }
  }
  const std::string task_set = task_set_identity(provenance);
  return task_set.empty() ? "unknown" : "task set " + task_set;
}

LeaderboardRun load_leaderboard_run(const std::filesystem::path& dir) {
  std::filesystem::path named = std::filesystem::absolute(dir).lexically_normal();
  if (!named.has_filename()) named = named.parent_path();  // "runs/a/"
  RunRows rows = load_run_rows(dir, named.filename().string());
  nlohmann::json provenance;
  std::string aid = "both";  // plans from before the aid was a choice gave words and close-ups
  if (std::filesystem::exists(dir / "plan.json")) {
    const nlohmann::json plan = read_json_file(dir / "plan.json");
    if (plan.is_object() && plan.contains("provenance")) provenance = plan["provenance"];
    if (plan.is_object() && plan.contains("lookalike_aid") && plan["lookalike_aid"].is_string()) {
      aid = plan["lookalike_aid"].get<std::string>();
    }
  }
  // A run told look-alikes by words alone or images alone measures something else than the
  // paper's setting: its own board (docs/statistics.md).
  std::string suite = suite_identity(provenance);
  if (aid != "both") suite += ", look-alike aid " + aid;
  return {std::move(rows.name), std::move(rows.rows), std::move(suite), rows.per_repeat};
}

nlohmann::json make_leaderboard(const std::vector<LeaderboardRun>& runs) {
  std::set<std::string> names;
  std::vector<std::string> suites;  // in the order first given
  std::map<std::string, std::vector<const LeaderboardRun*>> by_suite;
  for (const LeaderboardRun& run : runs) {
    if (!names.insert(run.name).second) {
      throw Error("two runs named " + run.name + ": their entrants could not be told apart; give folders of different names");
    }
    if (by_suite.count(run.suite) == 0) suites.push_back(run.suite);
    by_suite[run.suite].push_back(&run);
  }
  nlohmann::json boards = nlohmann::json::array();
  for (const std::string& suite : suites) {
    nlohmann::json board = board_json(suite, by_suite[suite]);
    if (suites.size() > 1) {
      std::string others;
      for (const std::string& other : suites) {
        if (other == suite) continue;
        std::string members;
        for (const LeaderboardRun* r : by_suite[other]) members += (members.empty() ? "" : ", ") + r->name;
        others += (others.empty() ? "" : "; ") + other + " (" + members + ")";
      }
      board["notes"].push_back("runs of other suites are on boards of their own, never ranked against these: " + others);
    }
    boards.push_back(std::move(board));
  }
  return {{"boards", boards}};
}

std::string leaderboard_text(const nlohmann::json& leaderboard) {
  std::ostringstream o;
  for (const auto& board : leaderboard["boards"]) {
    o << "Suite " << board["suite"].get<std::string>() << " (run" << (board["runs"].size() == 1 ? " " : "s ")
      << joined(board["runs"], ", ") << "): " << board["entrants"].size() << " entrant"
      << (board["entrants"].size() == 1 ? "" : "s") << ", ranked by SR; 95 % intervals; ranks and groups from exact "
      << "McNemar tests on the (task, repeat) pairs each two ran, Holm over " << tested_pairs(board) << " pair"
      << (tested_pairs(board) == 1 ? "" : "s") << "\n";
    std::size_t width = 9;
    for (const auto& e : board["entrants"]) width = std::max(width, e["label"].get<std::string>().size() + 2);
    o << "  " << padded("rank", 7) << padded("entrant", width) << padded("episodes", 10) << padded("SR % [95 % CI]", 23)
      << padded("IP [95 % CI]", 23) << "groups\n";
    for (const auto& e : board["entrants"]) {
      o << "  " << padded(rank_text(e), 7) << padded(e["label"].get<std::string>(), width)
        << padded(std::to_string(e["episodes"].get<std::int64_t>()), 10) << padded(with_interval(e, "sr"), 23)
        << padded(with_interval(e, "ip"), 23) << joined(e["groups"], "") << "\n";
    }
    for (const auto& g : board["groups"]) {
      if (g.size() > 1) o << "  " << tied_line(board, g) << "\n";
    }
    for (const auto& p : board["pairs"]) {
      if (p.contains("note")) o << "  " << p["a"].get<std::string>() << " and " << p["b"].get<std::string>() << ": " << p["note"].get<std::string>() << "\n";
    }
    for (const auto& note : board["notes"]) o << "  note: " << note.get<std::string>() << "\n";
  }
  return o.str();
}

std::string leaderboard_markdown(const nlohmann::json& leaderboard) {
  std::ostringstream o;
  o << "## Leaderboard\n";
  for (const auto& board : leaderboard["boards"]) {
    o << "\n### Suite `" << board["suite"].get<std::string>() << "`\n\n";
    o << "Run" << (board["runs"].size() == 1 ? "" : "s") << ": " << markdown_cell(joined(board["runs"], ", ")) << ".\n\n";
    o << "| rank | entrant | episodes | SR % [95 % CI] | IP [95 % CI] | groups |\n";
    o << "|---:|:---|---:|---:|---:|:---:|\n";
    for (const auto& e : board["entrants"]) {
      o << "| " << rank_text(e) << " | " << markdown_cell(e["label"].get<std::string>()) << " | " << e["episodes"] << " | "
        << with_interval(e, "sr") << " | " << with_interval(e, "ip") << " | " << joined(e["groups"], "") << " |\n";
    }
    o << "\n";
    for (const auto& g : board["groups"]) {
      if (g.size() > 1) o << "- " << markdown_cell(tied_line(board, g)) << "\n";
    }
    for (const auto& p : board["pairs"]) {
      if (p.contains("note")) {
        o << "- " << markdown_cell(p["a"].get<std::string>() + " and " + p["b"].get<std::string>()) << ": "
          << p["note"].get<std::string>() << "\n";
      }
    }
    for (const auto& note : board["notes"]) o << "- " << markdown_cell(note.get<std::string>()) << "\n";
    o << "\nRanked by SR. A rank range is what the paired tests leave open (exact McNemar on the (task, repeat) "
         "pairs each two entrants ran, Holm over the board's "
      << tested_pairs(board) << " tested pair" << (tested_pairs(board) == 1 ? "" : "s") << ", "
      << percent_text(board["alpha"].get<double>())
      << "); entrants sharing a group letter are not told apart (docs/statistics.md, \"Leaderboard\").\n";
  }
  return o.str();
}

}  // namespace mtg::orchestrator
