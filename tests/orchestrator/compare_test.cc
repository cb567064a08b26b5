// Paired comparisons and the report's intervals on results made here, where every figure can be
// worked out by hand.
#include <gtest/gtest.h>

#include <map>

#include "core/util/error.h"
#include "orchestrator/report/compare.h"
#include "orchestrator/report/report.h"
#include "tests/support/result_rows.h"

namespace mtg::orchestrator {
namespace {

EpisodeRow row(std::uint32_t episode, const std::string& task, const std::string& agent, int level, bool success,
               double ip) {
  return testing::scored_row(episode, task, agent, level, success, ip);
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

TEST(Compare, RunsOnDifferentTaskSetsPairWithAWarning) {
  const auto rows = twelve_tasks();
  const RunRows a{"one", rows, {}, "/t/a.sqlite (config 1)"}, b{"two", rows, {}, "/t/b.sqlite (config 2)"};
  const nlohmann::json c = compare_runs(a, &b, "A", "");
  ASSERT_TRUE(c.contains("warning"));
  EXPECT_NE(c["warning"].get<std::string>().find("ran different task sets"), std::string::npos);
  EXPECT_NE(compare_text(c).find("warning: one and two ran different task sets"), std::string::npos);
  const RunRows same{"two", rows, {}, a.task_set};
  EXPECT_FALSE(compare_runs(a, &same, "A", "").contains("warning"));
  EXPECT_THROW(compare_runs(a, &b, "nobody", ""), Error);
  EXPECT_THROW(compare_runs(a, &b, "", "A"), Error) << "a baseline agent is for one run";
  EXPECT_EQ(compare_runs(a, nullptr, "", "")["comparisons"][0]["a"]["agent"], "A") << "the run's first agent";
}

// Nine of B's episodes excluded by a person (issue 55): the comparison says so, with the reason,
// and puts the nine A episodes left without a partner down to B's exclusions, not to A.
TEST(Compare, ExclusionsAreSaidPerSideWithReasonsAndTheUnpairedPutDownToThem) {
  std::vector<EpisodeRow> all;
  for (std::uint32_t t = 0; t < 12; ++t) {
    all.push_back(row(2 * t, "s/L1/" + std::to_string(t), "A", 1, true, 0));
    all.push_back(row(2 * t + 1, "s/L1/" + std::to_string(t), "B", 1, false, 0));
  }
  std::map<bus::EpisodeId, EpisodeMarks> marks;
  for (std::uint32_t t = 0; t < 9; ++t) {
    EpisodeMarks m;
    m.excluded = true;
    m.exclusion_reason = t < 6 ? "renderer glitch" : "typo in the task";
    marks[bus::EpisodeId(2 * t + 1)] = m;
  }
  const RunRows run = run_rows("r", all, marks, "", 0);
  ASSERT_EQ(run.excluded.size(), 9u);
  const nlohmann::json c = compare_runs(run, nullptr, "", "A");
  const auto& one = c["comparisons"][0];
  EXPECT_EQ(one["pairs"], 3);
  EXPECT_EQ(one["excluded_a"]["episodes"], 0);
  EXPECT_EQ(one["excluded_b"]["episodes"], 9);
  EXPECT_EQ(one["excluded_b"]["reasons"]["renderer glitch"], 6);
  EXPECT_EQ(one["excluded_b"]["reasons"]["typo in the task"], 3);
  EXPECT_EQ(one["unpaired_a"], 9);
  EXPECT_EQ(one["unpaired_a_excluded_in_b"], 9) << "A's unpaired episodes lost their partner to B's exclusions";
  EXPECT_EQ(one["unpaired_b_excluded_in_a"], 0);
  const std::string text = compare_text(c);
  EXPECT_NE(text.find("excluded by a person from B: 9 episode(s) (6 \"renderer glitch\"; 3 \"typo in the task\")"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("9 of A's because B's episode was excluded"), std::string::npos) << text;
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

TEST(ReportRepeats, PassAtKAndPassHatKPerAgentOnlyWhereTasksRepeat) {
  // t1: 2 of 3; t2: 0 of 3. pass@1 = (2/3 + 0)/2, pass@2 = (1 + 0)/2, pass^2 = (1/3 + 0)/2.
  std::vector<EpisodeRow> rows;
  std::uint32_t id = 0;
  for (int r = 0; r < 3; ++r) {
    rows.push_back(row(id++, "t1", "X", 1, r < 2, 0.0));
    rows.push_back(row(id++, "t2", "X", 1, false, 0.0));
    if (r == 0) rows.push_back(row(id++, "t1", "once", 1, true, 0.0));
  }
  const nlohmann::json r = make_report(rows, "run");
  const auto& rep = r["by_agent"]["X"]["repeats"];
  EXPECT_EQ(rep["tasks"], 2);
  EXPECT_EQ(rep["episodes_per_task"], nlohmann::json::parse("[3, 3]"));
  EXPECT_EQ(rep["pass_at_k"], nlohmann::json::parse("[33.3, 50.0, 50.0]"));
  EXPECT_EQ(rep["pass_hat_k"], nlohmann::json::parse("[33.3, 16.7, 0.0]"));
  EXPECT_EQ(rep["k_of_n"], nlohmann::json::parse(R"({"0/3": 1, "2/3": 1})"));
  EXPECT_FALSE(r["by_agent"]["once"].contains("repeats")) << "one episode per task: nothing to say";
  EXPECT_NE(repeats_html(r).find("pass@2 50.0"), std::string::npos) << repeats_html(r);
}

TEST(ReportUsage, AnEndpointOfOnesOwnHasAGuessedPriceAndSpendsNothing) {
  std::vector<EpisodeRow> rows{row(0, "t", "openai:gpt-4o", 1, true, 0), row(1, "t", "openai-compatible:http://h:1/v1:m", 1, true, 0)};
  for (auto& r : rows) {
    r.usage.model_calls = 2;
    r.usage.cost_usd = 0.5;
    r.usage.spent_usd = 0.5;
  }
  const nlohmann::json r = make_report(rows, "run");
  EXPECT_EQ(r["usage"]["openai:gpt-4o"]["price_known"], true);
  EXPECT_EQ(r["usage"]["openai-compatible:http://h:1/v1:m"]["price_known"], false);
  const std::string html = report_html(r);
  EXPECT_NE(html.find("0.5 (a guess)</td><td>&ndash;</td>"), std::string::npos) << html;
}

}  // namespace
}  // namespace mtg::orchestrator
