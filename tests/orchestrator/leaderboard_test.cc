// The leaderboard (orchestrator/report/leaderboard.h) and the result card (card.h) on results
// made here, where every p-value, group and rank range is worked out by hand.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "core/util/error.h"
#include "core/util/text.h"
#include "orchestrator/report/card.h"
#include "orchestrator/report/leaderboard.h"
#include "orchestrator/report/report.h"
#include "orchestrator/run/marks.h"
#include "orchestrator/run/results_db.h"
#include "orchestrator/run/run_plan.h"
#include "tests/support/result_rows.h"

namespace mtg::orchestrator {
namespace {

namespace fs = std::filesystem;

EpisodeRow row(std::uint32_t episode, const std::string& task, const std::string& agent, bool success) {
  return testing::scored_row(episode, task, agent, 1, success);
}

// Twenty tasks: A succeeds on all, B on all but t19, D on t0..t10 and t19 (12), C on none.
std::vector<EpisodeRow> four_agents() {
  std::vector<EpisodeRow> rows;
  std::uint32_t id = 0;
  for (int t = 0; t < 20; ++t) {
    const std::string task = "s/L1/" + std::to_string(t);
    rows.push_back(row(id++, task, "A", true));
    rows.push_back(row(id++, task, "B", t != 19));
    rows.push_back(row(id++, task, "C", false));
    rows.push_back(row(id++, task, "D", t <= 10 || t == 19));
  }
  return rows;
}

const nlohmann::json& pair_of(const nlohmann::json& board, const std::string& a, const std::string& b) {
  for (const auto& p : board["pairs"]) {
    if (p["a"] == a && p["b"] == b) return p;
  }
  throw std::runtime_error("no pair " + a + " / " + b);
}

void expect_relative(double actual, double expected) { EXPECT_NEAR(actual, expected, 1e-9 * expected) << expected; }

TEST(Leaderboard, McNemarHolmGroupsAndRankRangesOfFourEntrants) {
  const nlohmann::json lb = make_leaderboard({{"r", four_agents(), "suite@1", 0}});
  ASSERT_EQ(lb["boards"].size(), 1u);
  const nlohmann::json& board = lb["boards"][0];
  EXPECT_EQ(board["suite"], "suite@1");
  EXPECT_DOUBLE_EQ(board["alpha"].get<double>(), 0.05);
  ASSERT_EQ(board["entrants"].size(), 4u);
  std::vector<std::string> order;
  for (const auto& e : board["entrants"]) order.push_back(e["label"].get<std::string>());
  EXPECT_EQ(order, (std::vector<std::string>{"A", "B", "D", "C"})) << "SR 100, 95, 60, 0; one run: labels are agents";
  const auto& a = board["entrants"][0];
  EXPECT_EQ(a["run"], "r");
  EXPECT_EQ(a["episodes"], 20);
  EXPECT_DOUBLE_EQ(a["sr"].get<double>(), 100.0);
  EXPECT_EQ(a["sr_ci"], nlohmann::json::parse("[83.9, 100.0]"));  // Wilson 20 of 20
  EXPECT_EQ(board["entrants"][2]["sr_ci"], nlohmann::json::parse("[38.7, 78.1]"));  // Wilson 12 of 20

  // Discordant pairs and exact p = min(1, 2·P[X <= min]), X ~ Bin(n, 1/2):
  ASSERT_EQ(board["pairs"].size(), 6u);
  const auto& ab = pair_of(board, "A", "B");
  EXPECT_EQ(ab["pairs"], 20);
  EXPECT_EQ(ab["only_a"], 1);
  EXPECT_EQ(ab["only_b"], 0);
  EXPECT_DOUBLE_EQ(ab["p"].get<double>(), 1.0);  // 2 · 1/2
  const auto& ad = pair_of(board, "A", "D");
  EXPECT_EQ(ad["only_a"], 8);
  expect_relative(ad["p"].get<double>(), std::ldexp(1.0, -7));  // 2 · 2^-8
  expect_relative(pair_of(board, "A", "C")["p"].get<double>(), std::ldexp(1.0, -19));
  const auto& bd = pair_of(board, "B", "D");
  EXPECT_EQ(bd["only_a"], 8);
  EXPECT_EQ(bd["only_b"], 1);
  expect_relative(bd["p"].get<double>(), 20.0 / 512.0);  // 2 · (1 + 9) / 2^9
  expect_relative(pair_of(board, "B", "C")["p"].get<double>(), std::ldexp(1.0, -18));
  expect_relative(pair_of(board, "D", "C")["p"].get<double>(), std::ldexp(1.0, -11));

  // Holm over the 6 pairs: the i-th smallest times 6 - i + 1.
  expect_relative(pair_of(board, "A", "C")["p_holm"].get<double>(), 6 * std::ldexp(1.0, -19));
  expect_relative(pair_of(board, "B", "C")["p_holm"].get<double>(), 5 * std::ldexp(1.0, -18));
  expect_relative(pair_of(board, "D", "C")["p_holm"].get<double>(), 4 * std::ldexp(1.0, -11));
  expect_relative(ad["p_holm"].get<double>(), 3 * std::ldexp(1.0, -7));
  expect_relative(bd["p_holm"].get<double>(), 2 * 20.0 / 512.0);
  EXPECT_DOUBLE_EQ(ab["p_holm"].get<double>(), 1.0);
  EXPECT_EQ(ab["significant"], false);
  EXPECT_EQ(bd["significant"], false) << "0.039 alone, 0.078 after Holm";
  EXPECT_EQ(ad["significant"], true);
  EXPECT_EQ(pair_of(board, "D", "C")["significant"], true);

  // A~B and B~D, but A is separated from D: two overlapping groups, and C alone.
  EXPECT_EQ(board["groups"], nlohmann::json::parse(R"j([["A", "B"], ["B", "D"], ["C"]])j"));
  const std::vector<std::pair<std::int64_t, std::int64_t>> ranks{{1, 2}, {1, 3}, {2, 3}, {4, 4}};
  const std::vector<nlohmann::json> letters{nlohmann::json::parse(R"(["a"])"), nlohmann::json::parse(R"(["a", "b"])"),
                                            nlohmann::json::parse(R"(["b"])"), nlohmann::json::parse(R"(["c"])")};
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& e = board["entrants"][i];
    EXPECT_EQ(e["rank_best"], ranks[i].first) << order[i];
    EXPECT_EQ(e["rank_worst"], ranks[i].second) << order[i];
    EXPECT_EQ(e["groups"], letters[i]) << order[i];
  }

  const std::string text = leaderboard_text(lb);
  EXPECT_NE(text.find("tied (no paired test separates them, Holm 5 %): A, B\n"), std::string::npos) << text;
  EXPECT_NE(text.find("tied (no paired test separates them, Holm 5 %): B, D\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("): C\n"), std::string::npos) << "a group of one ties nobody: " << text;
  EXPECT_NE(text.find("1–3"), std::string::npos) << text;
  const std::string md = leaderboard_markdown(lb);
  EXPECT_NE(md.find("| 1–2 | A | 20 | 100.0 [83.9, 100.0] | 100.0 [100.0, 100.0] | a |"), std::string::npos) << md;
  EXPECT_EQ(lb.dump(), make_leaderboard({{"r", four_agents(), "suite@1", 0}}).dump()) << "the same bytes";
}

TEST(Leaderboard, TwoSuitesAreTwoBoardsNeverRankedTogether) {
  const auto rows = four_agents();
  const nlohmann::json lb = make_leaderboard({{"one", rows, "suite@1", 0}, {"two", rows, "suite@2", 0}});
  ASSERT_EQ(lb["boards"].size(), 2u);
  for (std::size_t b = 0; b < 2; ++b) {
    const auto& board = lb["boards"][b];
    EXPECT_EQ(board["suite"], b == 0 ? "suite@1" : "suite@2");
    EXPECT_EQ(board["runs"], nlohmann::json::array({b == 0 ? "one" : "two"}));
    EXPECT_EQ(board["entrants"].size(), 4u) << "each board holds its own run only";
    EXPECT_EQ(board["entrants"][0]["label"], "A") << "one run per board: labels are agents";
    ASSERT_EQ(board["notes"].size(), 1u);
    EXPECT_NE(board["notes"][0].get<std::string>().find("boards of their own"), std::string::npos);
  }
  EXPECT_NE(lb["boards"][0]["notes"][0].get<std::string>().find("suite@2 (two)"), std::string::npos);
  EXPECT_THROW(make_leaderboard({{"one", rows, "suite@1", 0}, {"one", rows, "suite@1", 0}}), Error)
      << "two runs of one name";
}

TEST(Leaderboard, SeveralRunsAreLabelledAndPairsWithoutACommonTaskAreNotTested) {
  std::vector<EpisodeRow> one, two;
  std::uint32_t id = 0;
  for (int t = 0; t < 6; ++t) one.push_back(row(id++, "t" + std::to_string(t), "X", true));
  id = 0;
  for (int t = 0; t < 6; ++t) {
    two.push_back(row(id++, "u" + std::to_string(t), "X", t < 3));
    two.push_back(row(id++, "t" + std::to_string(t), "Y", false));
  }
  const nlohmann::json lb = make_leaderboard({{"one", one, "s", 0}, {"two", two, "s", 0}});
  ASSERT_EQ(lb["boards"].size(), 1u);
  const auto& board = lb["boards"][0];
  std::vector<std::string> order;
  for (const auto& e : board["entrants"]) order.push_back(e["label"].get<std::string>());
  EXPECT_EQ(order, (std::vector<std::string>{"X (one)", "X (two)", "Y (two)"}));
  const auto& untested = pair_of(board, "X (one)", "X (two)");
  EXPECT_EQ(untested["pairs"], 0);
  EXPECT_DOUBLE_EQ(untested["p"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(untested["p_holm"].get<double>(), 1.0);
  EXPECT_EQ(untested["note"], "no task ran on both: not tested");
  // The one tested pair is a family of one: 2 · 2^-6, not tripled by the pairs never tested.
  const auto& tested = pair_of(board, "X (one)", "Y (two)");
  EXPECT_EQ(tested["only_a"], 6);
  expect_relative(tested["p_holm"].get<double>(), 1.0 / 32.0);
  EXPECT_EQ(tested["significant"], true);
  EXPECT_EQ(board["groups"], nlohmann::json::parse(R"j([["X (one)", "X (two)"], ["X (two)", "Y (two)"]])j"));
  EXPECT_EQ(board["entrants"][1]["rank_best"], 1);
  EXPECT_EQ(board["entrants"][1]["rank_worst"], 3);
  EXPECT_NE(leaderboard_text(lb).find("X (one) and X (two): no task ran on both: not tested"), std::string::npos);
}

TEST(Leaderboard, TheSuiteIsTheDeclaredOneElseTheTaskSet) {
  EXPECT_EQ(suite_identity(nlohmann::json::parse(R"j({"suite": {"id": "standard-replicacad@1a2b"}, "task_set": {"config_hash": "c"}})j")),
            "standard-replicacad@1a2b");
  EXPECT_EQ(suite_identity(nlohmann::json::parse(R"j({"task_set": {"config_hash": "c"}, "dataset": {"apt_0": "d0"}})j")),
            "task set config c, apt_0 d0");
  EXPECT_EQ(suite_identity(nullptr), "unknown");
  const nlohmann::json lb = make_leaderboard({{"old", four_agents(), suite_identity(nullptr), 0}});
  EXPECT_NE(lb["boards"][0]["notes"].dump().find("planned before provenance"), std::string::npos);
}

// A run folder made here: results.sqlite, plan.json with provenance, and a person's exclusion.
fs::path make_run_folder(const std::string& name,
                         episode::LookalikeAid aid = episode::LookalikeAid::kBoth) {
  const fs::path dir = fs::temp_directory_path() / ("mtg_leaderboard_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  RunPlan plan;
  plan.run_id = name + "-0000abcd";
  plan.tasks_db = "/t/tasks.sqlite";
  plan.agents = {"oracle", "random"};
  plan.lookalike_aid = aid;
  {
    ResultsDb db(dir / "results.sqlite");
    std::uint32_t id = 0;
    for (int t = 0; t < 4; ++t) {
      const std::string task = "apt_0/L1/" + std::to_string(t);
      for (const std::string agent : {"oracle", "random"}) {
        plan.episodes.push_back({bus::EpisodeId(id), task, agent, id});
        db.insert(row(id++, task, agent, agent == "oracle" || t == 0));
      }
    }
  }
  plan.provenance = {{"mtg_version", "1.2.3"},
                     {"git_revision", "abc123"},
                     {"command", {"mtg", "run", "--agent", "oracle"}},
                     {"host", "lab-1"},
                     {"planned_at", "2026-11-28T10:58:03Z"},
                     {"task_set", {{"file", "/t/tasks.sqlite"}, {"config_hash", "c"}, {"bytes", 1}}},
                     {"dataset", {{"apt_0", "d0"}}},
                     {"suite", {{"id", "standard-replicacad@1a2b3c4d5e6f"}}},
                     {"model_settings", nullptr}};
  save_plan(plan, dir);
  add_mark(dir, {bus::EpisodeId(7), MarkAction::kExclude, "", "the goal already held", "ada", "2026-11-28T11:00:00Z"});
  return dir;
}

TEST(Leaderboard, ARunFolderLoadsWithItsSuiteAndWithoutItsExclusions) {
  const fs::path dir = make_run_folder("lb-run");
  const LeaderboardRun run = load_leaderboard_run(dir);
  EXPECT_EQ(run.name, "lb-run");
  EXPECT_EQ(run.suite, "standard-replicacad@1a2b3c4d5e6f");
  EXPECT_EQ(run.per_repeat, 8);
  EXPECT_EQ(run.rows.size(), 7u) << "episode 7 was excluded";
  EXPECT_THROW(load_leaderboard_run(dir / "missing"), Error);
  fs::remove_all(dir.parent_path());
}

// Runs of one suite told look-alikes by the words alone (--lookalike-aid words) measure another
// thing than the paper's words and close-ups: they are ranked on a board of their own.
TEST(Leaderboard, ARunWithAnotherLookalikeAidIsOnABoardOfItsOwn) {
  const LeaderboardRun both = load_leaderboard_run(make_run_folder("lb-both"));
  const LeaderboardRun words = load_leaderboard_run(make_run_folder("lb-words", episode::LookalikeAid::kWords));
  EXPECT_EQ(both.suite, "standard-replicacad@1a2b3c4d5e6f");
  EXPECT_EQ(words.suite, "standard-replicacad@1a2b3c4d5e6f, look-alike aid words");
  const nlohmann::json lb = make_leaderboard({both, words});
  ASSERT_EQ(lb["boards"].size(), 2u);
  EXPECT_EQ(lb["boards"][1]["suite"], "standard-replicacad@1a2b3c4d5e6f, look-alike aid words");
  fs::remove_all(fs::temp_directory_path() / ("mtg_leaderboard_" + std::to_string(::getpid())));
}

TEST(ResultCard, AFolderGetsItsSuiteFiguresProvenanceExclusionsAndCitation) {
  const fs::path dir = make_run_folder("card-run");
  write_card(dir);
  ASSERT_TRUE(fs::exists(dir / "card.json"));
  const std::string md = read_text_file(dir / "card.md", "card");
  for (const std::string expected :
       {"# Result card: card-run\n", "- Suite: `standard-replicacad@1a2b3c4d5e6f`", "- Task set: config c, apt_0 d0",
        "- Agents: oracle, random", "- Episodes: 7 scored of 7", "None: no model agent ran.",
        "| oracle | L1 | 4 | 100.0 [51.0, 100.0] |", "| random | Avg (L1) | 3 |",
        "No model agent: nothing was spent on model calls.", "- git revision: abc123",
        "- command: `mtg run --agent oracle`", "- planned at: 2026-11-28T10:58:03Z on lab-1",
        "- episode 7: the goal already held", "## How to cite", "arXiv:2505.20726",
        "- The tool: ManiTaskGen-LCM 1.2.3 (revision abc123).", "- The suite: `standard-replicacad@1a2b3c4d5e6f`."}) {
    EXPECT_NE(md.find(expected), std::string::npos) << expected << "\n" << md;
  }
  fs::remove_all(dir.parent_path());
}

TEST(ResultCard, CostOnlyForModelAgentsAndNoProvenanceSaidPlainly) {
  std::vector<EpisodeRow> rows{row(0, "t", "openai:gpt-4o", true), row(1, "t", "human", false)};
  rows[0].usage.model_calls = 3;
  rows[0].usage.cost_usd = 0.25;
  rows[0].usage.spent_usd = 0.25;
  const nlohmann::json card = card_of(make_report(rows, "run"), nlohmann::json::object());
  EXPECT_EQ(card["suite"]["id"], "unknown");
  EXPECT_TRUE(card["provenance"].is_null());
  EXPECT_TRUE(card["cost"].contains("openai:gpt-4o"));
  EXPECT_FALSE(card["cost"].contains("human")) << "a person's episodes cost nothing";
  EXPECT_EQ(card["agents"], nlohmann::json::parse(R"j(["human", "openai:gpt-4o"])j")) << "without a plan: the report's agents";
  const std::string md = card_markdown(card);
  EXPECT_NE(md.find("| openai:gpt-4o | 3 |"), std::string::npos) << md;
  EXPECT_NE(md.find("predates provenance"), std::string::npos) << md;
  EXPECT_NE(md.find("## Episodes excluded by a person\n\nNone."), std::string::npos) << md;
}

}  // namespace
}  // namespace mtg::orchestrator
