// The hang rule: slow (silent but working) is told from hung (stopped or blocked), on the pure rule
// and on what /proc says of real processes.
#include "orchestrator/run/hang_rule.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "orchestrator/run/process_memory.h"

namespace mtg::orchestrator {
namespace {

TEST(HangRule, LimitsFollowTheEpisodeTimeout) {
  EXPECT_DOUBLE_EQ(hang_limits(60).hang_after_s, 48);
  EXPECT_DOUBLE_EQ(hang_limits(60).runaway_after_s, 120);
  EXPECT_DOUBLE_EQ(hang_limits(1).hang_after_s, 3);  // never below 3 s
  EXPECT_DOUBLE_EQ(hang_limits(1).runaway_after_s, 3);
}

TEST(HangRule, SilenceIsJudgedByProgress) {
  const HangLimits l = hang_limits(20);  // 16 s, 40 s
  EXPECT_EQ(classify({10, 10, false}, l), Silence::kBeating);
  EXPECT_EQ(classify({10, 10, true}, l), Silence::kBeating);   // stopped only briefly so far
  EXPECT_EQ(classify({17, 0.5, false}, l), Silence::kSlow);    // working: left alone
  EXPECT_EQ(classify({39, 0.5, false}, l), Silence::kSlow);
  EXPECT_EQ(classify({41, 0.5, false}, l), Silence::kRunaway); // working too long without a beat
  EXPECT_EQ(classify({17, 17, false}, l), Silence::kHung);     // blocked all along
  EXPECT_EQ(classify({30, 16.5, false}, l), Silence::kHung);   // worked, then blocked
  EXPECT_EQ(classify({17, 0.5, true}, l), Silence::kHung);     // stopped by a signal
}

TEST(HangRule, ProgressIsCpuOrARunningOrDiskState) {
  EXPECT_TRUE(made_progress({'S', 1.0}, {'S', 1.01}));
  EXPECT_FALSE(made_progress({'S', 1.0}, {'S', 1.0}));
  EXPECT_TRUE(made_progress({'S', 1.0}, {'R', 1.0}));  // runnable, starved of CPU on a loaded machine
  EXPECT_TRUE(made_progress({'S', 1.0}, {'D', 1.0}));
  EXPECT_FALSE(made_progress({'R', 1.0}, {'T', 1.5}));  // stopped now, whatever it did before
}

// Forks a child that runs `body` until killed.
template <typename Body>
pid_t child(Body body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    body();
    ::_exit(0);
  }
  return pid;
}

void reap(pid_t pid) {
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
}

// What the rule sees of `pid` over 0.6 s.
bool progressed(pid_t pid) {
  const auto before = main_thread_activity(pid);
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  const auto after = main_thread_activity(pid);
  return before && after && made_progress(*before, *after);
}

TEST(HangRule, RealProcessesAreToldApart) {
  const pid_t busy = child([] {
    volatile unsigned long n = 0;
    for (;;) n = n + 1;
  });
  const pid_t blocked = child([] {
    for (;;) ::pause();
  });
  const pid_t stopped = child([] {
    volatile unsigned long n = 0;
    for (;;) n = n + 1;
  });
  ASSERT_GT(busy, 0);
  ASSERT_GT(blocked, 0);
  ASSERT_GT(stopped, 0);
  ::kill(stopped, SIGSTOP);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_TRUE(progressed(busy));
  EXPECT_FALSE(progressed(blocked));
  EXPECT_FALSE(progressed(stopped));
  const auto s = main_thread_activity(stopped);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->state, 'T');
  reap(busy);
  reap(blocked);
  reap(stopped);
  EXPECT_FALSE(main_thread_activity(busy).has_value());  // gone
}

}  // namespace
}  // namespace mtg::orchestrator
