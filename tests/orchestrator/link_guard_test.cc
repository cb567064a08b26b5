// A link planted at any name a run writes is never written through (issue 55): a run, a resume, a
// report, a replay, a rejudge and a gather refuse it in one line before any work, and what it
// points at is left exactly as it was.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/store/sqlite.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "tests/support/run_fixture.h"

namespace mtg {
namespace {

namespace fs = std::filesystem;

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class LinkGuardTest : public testing::RunFixture {
 protected:
  // A file of someone else's the link points at, with content the test checks afterwards.
  fs::path victim(const std::string& name) {
    const fs::path v = fx_.root() / ("victim-" + name);
    std::ofstream(v, std::ios::binary) << "precious " << name << "\n";
    return v;
  }
  std::string last_line() const {
    std::istringstream in(log_text());
    std::string line, last;
    while (std::getline(in, line)) {
      if (!line.empty()) last = line;
    }
    return last;
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
    const std::string before = contents(target);
    fs::create_symlink(target, at);
    EXPECT_EQ(mtg(run_args("run", {"oracle"}, 1, 2)), 1) << log_text();
    EXPECT_NE(last_line().find(at.string() + ": is a symbolic link"), std::string::npos) << log_text();
    EXPECT_EQ(contents(target), before) << "the run wrote through the link at " << name;
    fs::remove(at);
    if (existed) fs::rename(kept, at);
  }
  // The same for the commands that write into a finished run's folder.
  const fs::path target = victim("report");
  const std::string before = contents(target);
  fs::rename(dir / "report.png", fx_.root() / "kept.png");
  fs::create_symlink(target, dir / "report.png");
  EXPECT_EQ(mtg({testing::bin("mtg"), "report", dir.string()}), 1) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "report", dir.string(), "--card"}), 1) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "rejudge", dir.string()}), 1) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "replay", dir.string()}), 1) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "gather", dir.string(), "--no-bus"}), 1) << log_text();
  EXPECT_NE(last_line().find("report.png: is a symbolic link"), std::string::npos) << log_text();
  EXPECT_EQ(contents(target), before);
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
  EXPECT_EQ(contents(target), "precious lock\n");
  EXPECT_FALSE(fs::exists(dir / "plan.json")) << "nothing is written before the check";
  // A folder the run writes into, planted as a link to elsewhere.
  fs::remove(dir / ".lock");
  fs::create_directories(fx_.root() / "elsewhere");
  fs::create_directory_symlink(fx_.root() / "elsewhere", dir / "logs");
  EXPECT_EQ(mtg(run_args("evalrun", {"oracle"}, 1, 2)), 1) << log_text();
  EXPECT_NE(last_line().find("logs: is a symbolic link"), std::string::npos) << log_text();
  EXPECT_TRUE(fs::is_empty(fx_.root() / "elsewhere"));
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

}  // namespace
}  // namespace mtg
