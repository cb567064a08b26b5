// Paired comparisons and the report's intervals on results made here, where every figure can be
// worked out by hand.
#include <gtest/gtest.h>

#include "core/util/error.h"
#include "orchestrator/report/compare.h"
#include "orchestrator/report/report.h"

namespace mtg::orchestrator {
namespace {

EpisodeRow row(std::uint32_t episode, const std::string& task, const std::string& agent, int level, bool success,
               double ip) {
  EpisodeRow r;
  r.episode_id = bus::EpisodeId(episode);
  r.task_id = task;
  r.agent = agent;
  r.level = level;
  r.success = success;
  r.ip = success ? 100.0 : ip;
  r.stage = success ? "done" : "start";
  r.cause = success ? "" : "navigation";
  return r;
}

// 12 tasks of Level 1: A succeeds on 10, B on 3; A alone on 8, B alone on 1.
std::vector<EpisodeRow> twelve_tasks() {
  std::vector<EpisodeRow> rows;
  std::uint32_t id = 0;
  for (int t = 0; t < 12; ++t) {
    const std::string task = "s/L1/" + std::to_string(t);
    const bool a = t < 10, b = t < 2 || t == 11;
    rows.push_back(row(id++, task, "A", 1, a, 25.0));
    rows.push_back(row(id++, task, "B", 1, b, 50.0));
  }
  return rows;
}

TEST(Compare, McNemarAndTheFlipsComeFromThePairs) {
  const auto rows = twelve_tasks();
  const nlohmann::json c = compare_sides({{"r", "A", rows}}, {{"r", "B", rows}});
  const auto& one = c["comparisons"][0];
  EXPECT_EQ(one["pairs"], 12);
  const auto& all = one["levels"]["all"];
  EXPECT_EQ(all["only_a"], 8);
  EXPECT_EQ(all["only_b"], 1);
  EXPECT_NEAR(all["sr_p"].get<double>(), 2.0 * 10.0 / 512.0, 1e-12);  // 2·P[X <= 1], X ~ Bin(9, 1/2)
  EXPECT_DOUBLE_EQ(all["sr_p_holm"].get<double>(), all["sr_p"].get<double>()) << "one comparison: nothing to adjust";
  EXPECT_DOUBLE_EQ(all["sr_diff"].get<double>(), -58.3);  // (3 - 10) / 12
  EXPECT_LT(all["sr_diff_ci"][0].get<double>(), -58.3);
  EXPECT_GT(all["sr_diff_ci"][1].get<double>(), -58.3);
  EXPECT_LT(all["sr_diff_ci"][1].get<double>(), 0.0);
  EXPECT_EQ(one["regression_count"], 8);
  EXPECT_EQ(one["improvement_count"], 1);
  EXPECT_EQ(one["improvements"][0]["task"], "s/L1/11");
  EXPECT_EQ(one["improvements"][0]["episode_a"], 22);
  EXPECT_EQ(one["improvements"][0]["episode_b"], 23);
  EXPECT_EQ(c.dump(), compare_sides({{"r", "A", rows}}, {{"r", "B", rows}}).dump()) << "seeded: the same bytes";
  const std::string text = compare_text(c);
  EXPECT_NE(text.find("8 regressions"), std::string::npos) << text;
  EXPECT_NE(text.find("SR: B is lower by 58.3 points, significant"), std::string::npos) << text;
}

TEST(Compare, RepeatsPairInOrderAndTheUnpairedAreCounted) {
  std::vector<EpisodeRow> a{row(0, "t", "X", 2, true, 0), row(5, "t", "X", 2, false, 25), row(9, "u", "X", 2, true, 0)};
  std::vector<EpisodeRow> b{row(1, "t", "X", 2, false, 0), row(3, "t", "X", 2, false, 25)};
  const nlohmann::json c = compare_sides({{"one", "X", a}}, {{"two", "X", b}});
  const auto& one = c["comparisons"][0];
  EXPECT_EQ(one["pairs"], 2);
  EXPECT_EQ(one["unpaired_a"], 1);
  EXPECT_EQ(one["unpaired_b"], 0);
  EXPECT_EQ(one["regressions"][0]["episode_a"], 0);  // repeat 0 with repeat 0
  EXPECT_EQ(one["regressions"][0]["episode_b"], 1);
  EXPECT_EQ(one["levels"]["2"]["pairs"], 2);
  const std::string text = compare_text(c);
  EXPECT_NE(text.find("not significant"), std::string::npos) << text;
}

TEST(Compare, HolmAdjustsAcrossTheAgentsCompared) {
  const auto rows = twelve_tasks();
  std::vector<EpisodeRow> same = rows;
  for (auto& r : same) {
    if (r.agent == "A") r.agent = "C";
  }
  for (const auto& r : rows) {
    if (r.agent == "A") same.push_back(r);
  }
  const nlohmann::json c = compare_sides({{"r", "A", same}, {"r", "A", same}}, {{"r", "B", same}, {"r", "C", same}});
  const auto& b = c["comparisons"][0]["levels"]["all"];
  const auto& same_as_a = c["comparisons"][1]["levels"]["all"];
  EXPECT_DOUBLE_EQ(same_as_a["sr_p"].get<double>(), 1.0);
  EXPECT_NEAR(b["sr_p_holm"].get<double>(), 2.0 * b["sr_p"].get<double>(), 1e-12);  // smallest of 2, times 2
  EXPECT_DOUBLE_EQ(same_as_a["sr_p_holm"].get<double>(), 1.0);
}

TEST(Compare, SidesWithoutACommonTaskAreRefusedByName) {
  const std::vector<EpisodeRow> a{row(0, "t", "X", 1, true, 0)}, b{row(1, "u", "X", 1, true, 0)};
  try {
    compare_sides({{"one", "X", a}}, {{"two", "X", b}});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("one/X vs two/X: no task ran on both sides"), std::string::npos) << e.what();
  }
}

TEST(ReportIntervals, EveryRateHasItsIntervalAndTheAverageIsOverTheLevelsRun) {
  std::vector<EpisodeRow> rows;
  std::uint32_t id = 0;
  for (int i = 0; i < 6; ++i) rows.push_back(row(id++, "L1/" + std::to_string(i), "human", 1, i < 5, 0.0));
  for (int i = 0; i < 4; ++i) rows.push_back(row(id++, "L2/" + std::to_string(i), "human", 2, i < 1, 25.0));
  const nlohmann::json r = make_report(rows, "run");
  const auto& l1 = r["by_agent"]["human"]["by_level"]["1"];
  EXPECT_DOUBLE_EQ(l1["sr"].get<double>(), 83.3);
  EXPECT_EQ(l1["sr_ci"], nlohmann::json::parse("[43.6, 97.0]"));  // Wilson 5 of 6
  const auto& avg = r["by_agent"]["human"]["paper_avg"];
  EXPECT_EQ(avg["levels"], nlohmann::json::parse(R"(["1", "2"])"));
  EXPECT_DOUBLE_EQ(avg["sr"].get<double>(), 54.2);  // (83.3 + 25) / 2, not the pooled 60
  EXPECT_LT(avg["sr_ci"][0].get<double>(), 54.2);
  EXPECT_GT(avg["sr_ci"][1].get<double>(), 54.2);
  EXPECT_EQ(paper_average_label(r), "Avg (L1–2)");
  for (const char* key : {"sr_ci", "ip_ci"}) {
    ASSERT_TRUE(r.contains(key)) << key;
    EXPECT_LE(r[key][0].get<double>(), r[key == std::string("sr_ci") ? "sr" : "ip"].get<double>());
  }
  EXPECT_EQ(r.dump(), make_report(rows, "run").dump()) << "seeded: the same bytes";
  EXPECT_NE(report_html(r).find("43.6&ndash;97.0"), std::string::npos);
}

}  // namespace
}  // namespace mtg::orchestrator
