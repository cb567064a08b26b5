// A link planted at any name a run writes is never written through (issue 55): a run, a resume, a
// report, a replay, a rejudge and a gather refuse it in one line before any work, and what it
// points at is left exactly as it was.

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bus/recording_ref.h"
#include "core/store/sqlite.h"
#include "core/util/file_bytes.h"
#include "core/util/host_name.h"
#include "orchestrator/run/results_db.h"
#include "orchestrator/run/run_plan.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "tests/support/result_rows.h"
#include "tests/support/run_fixture.h"
#include "tests/support/text_file.h"

namespace mtg {
namespace {

namespace fs = std::filesystem;

class LinkGuardTest : public testing::RunFixture {
 protected:
  // A file of someone else's the link points at, with content the test checks afterwards.
  fs::path victim(const std::string& name) {
    const fs::path v = fx_.root() / ("victim-" + name);
    std::ofstream(v, std::ios::binary) << "precious " << name << "\n";
    return v;
  }
};

TEST_F(LinkGuardTest, ALinkAtAnyNameARunWritesIsRefusedAndItsTargetUntouched) {
  ASSERT_EQ(mtg(run_args("run", {"oracle"}, 1, 2)), 0) << log_text();
  const fs::path dir = fx_.root() / "run";
  // Every name a resume writes, in place or by rename; a link planted at each in turn.
  const std::vector<std::string> names = {".lock",          "plan.json",     "sessions.jsonl",   "results.sqlite",
                                          "results.sqlite-journal", "marks.sqlite", "report.html", "report.png",
                                          "report.json",    "bus.json",      "bus-0.lcmlog",     "logs/recorder.log"};
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const fs::path at = dir / name;
    const fs::path kept = fx_.root() / "kept";
    const bool existed = fs::exists(fs::symlink_status(at));
    if (existed) fs::rename(at, kept);
    const fs::path target = victim(fs::path(name).filename().string());
    const std::string before = testing::read_text(target);
    fs::create_symlink(target, at);
    EXPECT_EQ(mtg(run_args("run", {"oracle"}, 1, 2)), 1) << log_text();
    EXPECT_NE(last_line().find(at.string() + ": is a symbolic link"), std::string::npos) << log_text();
    EXPECT_EQ(testing::read_text(target), before) << "the run wrote through the link at " << name;
    fs::remove(at);
    if (existed) fs::rename(kept, at);
  }
  // The same for the commands that write into a finished run's folder.
  const fs::path target = victim("report");
  const std::string before = testing::read_text(target);
  fs::rename(dir / "report.png", fx_.root() / "kept.png");
  fs::create_symlink(target, dir / "report.png");
  EXPECT_EQ(mtg({testing::bin("mtg"), "report", dir.string()}), 1) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "report", dir.string(), "--card"}), 1) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "rejudge", dir.string()}), 1) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "replay", dir.string()}), 1) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "gather", dir.string(), "--no-bus"}), 1) << log_text();
  EXPECT_NE(last_line().find("report.png: is a symbolic link"), std::string::npos) << log_text();
  EXPECT_EQ(testing::read_text(target), before);
  fs::remove(dir / "report.png");
  fs::rename(fx_.root() / "kept.png", dir / "report.png");
  // With nothing planted, the folder resumes as before.
  EXPECT_EQ(mtg(run_args("run", {"oracle"}, 1, 2)), 0) << log_text();
}

TEST_F(LinkGuardTest, ANewRunFolderWithAPlantedLockIsRefusedBeforeAnything) {
  const fs::path dir = fx_.root() / "evalrun";
  fs::create_directories(dir);
  const fs::path target = victim("lock");
  fs::create_symlink(target, dir / ".lock");
  EXPECT_EQ(mtg(run_args("evalrun", {"oracle"}, 1, 2)), 1) << log_text();
  EXPECT_EQ(testing::read_text(target), "precious lock\n");
  EXPECT_FALSE(fs::exists(dir / "plan.json")) << "nothing is written before the check";
  // A folder the run writes into, planted as a link to elsewhere.
  fs::remove(dir / ".lock");
  fs::create_directories(fx_.root() / "elsewhere");
  fs::create_directory_symlink(fx_.root() / "elsewhere", dir / "logs");
  EXPECT_EQ(mtg(run_args("evalrun", {"oracle"}, 1, 2)), 1) << log_text();
  EXPECT_NE(last_line().find("logs: is a symbolic link"), std::string::npos) << log_text();
  EXPECT_TRUE(fs::is_empty(fx_.root() / "elsewhere"));
}

// The probe's own steps (issue 55): an ordinary user in a world-writable sticky folder makes a run
// folder and plants links in it, then root writes there. A run (.lock, report.png) and an export
// refuse in one line naming the link; a task set and a suite replace the link with their file; no
// target changes.
TEST_F(LinkGuardTest, LinksPlantedByAnotherUserInAStickyFolderAreNeverWrittenThrough) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to act as another user";
  const fs::path sticky = fx_.root() / "shared-tmp";
  fs::create_directories(sticky);
  fs::permissions(sticky, fs::perms::all | fs::perms::sticky_bit);
  fs::permissions(fx_.root(), fs::perms::others_exec, fs::perm_options::add);  // the other user reaches it
  const auto as_nobody = [&](const std::vector<std::string>& argv) {
    std::vector<std::string> full = {"/usr/bin/setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"};
    full.insert(full.end(), argv.begin(), argv.end());
    return mtg(full);
  };
  const fs::path lock_target = victim("root-lock");
  const fs::path png_target = victim("root-png");
  const fs::path tasks_target = victim("root-tasks");
  const fs::path suite_target = victim("root-suite");
  const fs::path index_target = victim("root-index");
  ASSERT_EQ(as_nobody({"/bin/mkdir", (sticky / "evalrun").string(), (sticky / "site").string()}), 0) << log_text();
  ASSERT_EQ(as_nobody({"/bin/ln", "-s", lock_target.string(), (sticky / "evalrun" / ".lock").string()}), 0);
  ASSERT_EQ(as_nobody({"/bin/ln", "-s", png_target.string(), (sticky / "evalrun" / "report.png").string()}), 0);
  ASSERT_EQ(as_nobody({"/bin/ln", "-s", tasks_target.string(), (sticky / "tasks.sqlite").string()}), 0);
  ASSERT_EQ(as_nobody({"/bin/ln", "-s", suite_target.string(), (sticky / "suite.json").string()}), 0);
  ASSERT_EQ(as_nobody({"/bin/ln", "-s", index_target.string(), (sticky / "site" / "index.html").string()}), 0);

  auto args = run_args("unused", {"oracle"}, 1, 2);
  args[std::distance(args.begin(), std::find(args.begin(), args.end(), "--out")) + 1] = (sticky / "evalrun").string();
  EXPECT_EQ(mtg(args), 1) << log_text();
  EXPECT_NE(last_line().find("evalrun/.lock: is a symbolic link"), std::string::npos) << log_text();
  EXPECT_FALSE(fs::exists(sticky / "evalrun" / "plan.json"));

  // Whole-file outputs go through the atomic writer: the link itself is replaced by root's file,
  // what it pointed at is not touched.
  EXPECT_EQ(mtg({testing::bin("mtg"), "tasks", "--data", fx_.root().string(), "--scene", "two_tables", "--levels",
                 "1,2", "--out", (sticky / "tasks.sqlite").string()}),
            0)
      << log_text();
  EXPECT_FALSE(fs::is_symlink(sticky / "tasks.sqlite"));
  EXPECT_EQ(mtg({testing::bin("mtg"), "suite", "make", "--tasks", tasks_db_, "--levels", "2", "--per-level", "1",
                 "--seed", "0", "--name", "s", "--out", (sticky / "suite.json").string()}),
            0)
      << log_text();
  EXPECT_FALSE(fs::is_symlink(sticky / "suite.json"));

  ASSERT_EQ(mtg(run_args("done", {"oracle"}, 1, 2)), 0) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "export", (fx_.root() / "done").string(), "--out", (sticky / "site").string()}), 1)
      << log_text();

  for (const auto& [target, name] : std::vector<std::pair<fs::path, std::string>>{
           {lock_target, "root-lock"}, {png_target, "root-png"}, {tasks_target, "root-tasks"},
           {suite_target, "root-suite"}, {index_target, "root-index"}}) {
    EXPECT_EQ(testing::read_text(target), "precious " + name + "\n") << target;
  }
}

// A dangling link at a database's name (a mark in `mtg view` opens marks.sqlite): SQLite would
// create the file it names.
TEST(LinkGuard, ADatabaseIsNeverOpenedForWritingThroughALink) {
  const fs::path dir = fs::temp_directory_path() / ("mtg_link_guard_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path nowhere = dir / "created-elsewhere.sqlite";
  fs::create_symlink(nowhere, dir / "marks.sqlite");
  EXPECT_THROW(store::Database(dir / "marks.sqlite", store::Database::Mode::kCreate), Error);
  EXPECT_FALSE(fs::exists(nowhere));
  fs::remove(dir / "marks.sqlite");
  fs::create_symlink(nowhere, dir / "marks.sqlite-journal");
  EXPECT_THROW(store::Database(dir / "marks.sqlite", store::Database::Mode::kCreate), Error);
  EXPECT_FALSE(fs::exists(nowhere));
  // The helpers name the file and why.
  try {
    require_plain_file(dir / "marks.sqlite-journal");
    ADD_FAILURE() << "a link was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a symbolic link"), std::string::npos) << e.what();
  }
  EXPECT_THROW(require_plain_file("/dev/null"), Error);
  EXPECT_NO_THROW(require_plain_file(dir / "absent"));
  fs::remove_all(dir);
}

// A key holder's reference to a file that is not the attempt's recording (issue 55: /etc/passwd,
// with its real size and hash, was once kept as four episodes' recordings and copied by gather).
TEST(RecordingRefs, AReferenceToAnotherFileIsNeverReadKeptNorCopied) {
  const fs::path dir = fs::temp_directory_path() / ("mtg_forged_ref_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "run");
  const fs::path secret = dir / "secret.txt";
  std::ofstream(secret, std::ios::binary) << "root:x:0:0:root:/root:/bin/bash\n";
  const auto bytes = read_file_bytes(secret);
  const bus::RecordingRef forged =
      bus::reference_to(bus::EpisodeId(0), 0, secret.string(), host_name(), false, bytes);  // the real size and hash
  EXPECT_NE(bus::check_recording(secret, forged).find("is not named E0-a0.lcmlog"), std::string::npos)
      << bus::check_recording(secret, forged);
  // Named as a recording but a link to the file: refused too.
  fs::create_directories(dir / "w" / "r-1" / "episodes");
  const fs::path link = dir / "w" / "r-1" / "episodes" / "E0-a0.lcmlog";
  fs::create_symlink(secret, link);
  bus::RecordingRef linked = forged;
  linked.location = link.string();
  EXPECT_NE(bus::check_recording(link, linked).find("symbolic link"), std::string::npos);
  // A size no recording has (a 3 GB sparse file) is refused before a byte is read.
  bus::RecordingRef huge = linked;
  huge.bytes = std::int64_t{3} << 30;
  EXPECT_NE(bus::recording_misfit(dir / "E0-a0.lcmlog", huge).find("bytes, outside"), std::string::npos);

  // gather finds the forged reference in a run folder and copies nothing.
  orchestrator::RunPlan plan;
  plan.run_id = "r-1";
  plan.agents = {"oracle"};
  plan.episodes.push_back({bus::EpisodeId(0), "s/L1/000000", "oracle", 0});
  orchestrator::save_plan(plan, dir / "run");
  {
    orchestrator::ResultsDb db(dir / "run" / "results.sqlite");
    ASSERT_TRUE(db.insert(testing::scored_row(0, "s/L1/000000", "oracle", 1, true), &forged));
  }
  testing::ChildProcess gather({testing::bin("mtg"), "gather", (dir / "run").string(), "--no-bus", "--from",
                                (dir / "w").string()},
                               (dir / "gather.log").string());
  EXPECT_EQ(gather.wait(60000), 1) << testing::read_text(dir / "gather.log");
  EXPECT_NE(testing::read_text(dir / "gather.log").find("1 missing"), std::string::npos) << testing::read_text(dir / "gather.log");
  EXPECT_FALSE(fs::exists(dir / "run" / "episodes" / "E0-a0.lcmlog")) << "the secret was copied as a recording";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mtg
