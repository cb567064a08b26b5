#include "orchestrator/run/run_lock.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <string>

#include "core/util/error.h"

namespace mtg::orchestrator {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

// Two runs on one --out split its episodes and interleave its recording: the second is refused
// with one line naming the first, and the folder is free again once the first is gone.
TEST(RunLock, ASecondWriterIsRefusedWithTheFirstNamed) {
  const fs::path dir = fresh_dir("mtg_run_lock");
  {
    const RunLock first(dir, "mtg run");
    try {
      const RunLock second(dir, "mtg play");
      ADD_FAILURE() << "the second writer was let in";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(dir.string() + " is in use by mtg run (process " + std::to_string(::getpid())), std::string::npos)
          << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  EXPECT_NO_THROW(RunLock again(dir));
  fs::remove_all(dir);
}

TEST(RunLock, AKilledRunLeavesNoLockBehind) {
  const fs::path dir = fresh_dir("mtg_run_lock_killed");
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const RunLock held(dir);
    const char c = 1;
    if (::write(ready[1], &c, 1) != 1) ::_exit(2);
    ::pause();  // killed here, the lock still held
    ::_exit(0);
  }
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  EXPECT_THROW(RunLock busy(dir), Error);
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_NO_THROW(RunLock resumed(dir)) << "a stale lock blocked the resume";
  ::close(ready[0]);
  ::close(ready[1]);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mtg::orchestrator
