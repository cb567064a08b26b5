// Marks (orchestrator/run/marks.h): what a change needs, the trail replayed, exclusions leaving
// the figures, and the report saying so.
#include "orchestrator/run/marks.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "core/util/error.h"
#include "orchestrator/report/report.h"

namespace mtg::orchestrator {
namespace {

MarkEntry entry(std::int64_t episode, MarkAction action, std::string tag = "", std::string reason = "") {
  return {bus::EpisodeId(episode), action, std::move(tag), std::move(reason), "ada", "2026-11-28T10:00:00Z"};
}

TEST(Marks, AChangeNamesItsPersonAndAnExclusionItsReason) {
  EXPECT_NO_THROW(check_mark(entry(1, MarkAction::kFlag)));
  MarkEntry anonymous = entry(1, MarkAction::kFlag);
  anonymous.who.clear();
  EXPECT_THROW(check_mark(anonymous), Error);
  EXPECT_THROW(check_mark(entry(1, MarkAction::kExclude)), Error);
  EXPECT_THROW(check_mark(entry(1, MarkAction::kTag)), Error) << "a tag needs its name";
  EXPECT_THROW(check_mark(entry(1, MarkAction::kFlag, "t")), Error) << "a tag only with tag or untag";
  EXPECT_THROW(check_mark(entry(1, MarkAction::kExclude, "", std::string(kMarkTextLimit + 1, 'x'))), Error);
  EXPECT_THROW(check_mark(entry(1, MarkAction::kExclude, "", "two\nlines")), Error);
  EXPECT_THROW(check_mark(entry(1, MarkAction::kExclude, "", " ")), Error) << "a blank reason says nothing";
  EXPECT_THROW(check_mark(entry(1, MarkAction::kInclude, "", " \t")), Error);
  EXPECT_EQ(mark_action_from_string("exclude"), MarkAction::kExclude);
  EXPECT_EQ(mark_action_from_string("delete"), std::nullopt);
}

TEST(Marks, TheTrailIsKeptAndReplayedInOrder) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("mtg_marks_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  EXPECT_TRUE(read_marks(dir).empty()) << "no file, no marks";
  add_mark(dir, entry(7, MarkAction::kFlag));
  add_mark(dir, entry(7, MarkAction::kTag, "odd"));
  add_mark(dir, entry(7, MarkAction::kExclude, "", "hidden item"));
  add_mark(dir, entry(8, MarkAction::kExclude, "", "duplicate"));
  add_mark(dir, entry(8, MarkAction::kInclude, "", "not a duplicate"));
  add_mark(dir, entry(7, MarkAction::kUnflag));
  const auto trail = read_marks(dir);
  ASSERT_EQ(trail.size(), 6u);
  EXPECT_EQ(trail[2].reason, "hidden item");
  const auto now = current_marks(trail);
  EXPECT_FALSE(now.at(bus::EpisodeId(7)).flagged);
  EXPECT_EQ(now.at(bus::EpisodeId(7)).tags, (std::set<std::string>{"odd"}));
  EXPECT_TRUE(now.at(bus::EpisodeId(7)).excluded);
  EXPECT_EQ(now.at(bus::EpisodeId(7)).exclusion_reason, "hidden item");
  EXPECT_FALSE(now.at(bus::EpisodeId(8)).excluded);
  std::filesystem::remove_all(dir);
}

TEST(Marks, AnExcludedEpisodeLeavesEveryFigureAndTheReportSaysWhy) {
  std::vector<EpisodeRow> rows(3);
  for (int i = 0; i < 3; ++i) {
    rows[static_cast<std::size_t>(i)].episode_id = bus::EpisodeId(i);
    rows[static_cast<std::size_t>(i)].task_id = "t" + std::to_string(i);
    rows[static_cast<std::size_t>(i)].agent = "a";
    rows[static_cast<std::size_t>(i)].level = 1;
    rows[static_cast<std::size_t>(i)].stage = "start";
    rows[static_cast<std::size_t>(i)].cause = "navigation";
  }
  rows[0].success = true;
  rows[0].ip = 100.0;
  rows[0].stage = "done";
  rows[0].cause = "";
  const auto marks = current_marks({entry(0, MarkAction::kExclude, "", "the goal already held")});
  EXPECT_EQ(without_excluded(rows, marks).size(), 2u);
  const nlohmann::json r = make_report(rows, "run", &marks);
  EXPECT_EQ(r["scored"], 2);
  EXPECT_DOUBLE_EQ(r["sr"].get<double>(), 0.0);
  EXPECT_EQ(r["excluded"][0]["reason"], "the goal already held");
  EXPECT_NE(report_html(r).find("1 episode(s) excluded by a person"), std::string::npos);
  const std::map<bus::EpisodeId, EpisodeMarks> none;
  EXPECT_EQ(make_report(rows, "run", &none).dump(), make_report(rows, "run").dump()) << "no marks, the same report";
}

}  // namespace
}  // namespace mtg::orchestrator
