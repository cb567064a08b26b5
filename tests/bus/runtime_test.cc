// The episode runtime end to end: `mtg run` with real processes on this test's own bus
// (`scripts/with-bus --isolated` gives every test its own network namespace), with the failures the issue
// names injected: killed processes, lost and duplicated messages, malformed replies.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/event_log.h"
#include "bus/header.h"
#include "bus/recording.h"
#include "bus/url.h"
#include "core/tasks/generator.h"
#include "core/tasks/task_db.h"
#include "mtg/episode_result_t.hpp"
#include "mtg/heartbeat_t.hpp"
#include "orchestrator/run/results_db.h"
#include "orchestrator/run/run_lock.h"
#include "tests/support/fixture_dataset.h"
#include "tests/support/graph_fixtures.h"
#include "orchestrator/run/provenance.h"
#include "tests/support/process.h"
#include "tests/support/run_fixture.h"
#include "tests/support/shipped_data.h"

namespace mtg {
namespace {

namespace fs = std::filesystem;
using orchestrator::EpisodeRow;

using RuntimeTest = testing::RunFixture;

TEST_F(RuntimeTest, EveryEpisodeOnceOracleAlwaysSucceedsReportHasTheContract) {
  ASSERT_EQ(mtg(run_args("run", {"oracle", "random"}, 6, 4)), 0) << log_text();
  const auto rows = results("run");
  ASSERT_EQ(rows.size(), planned("run"));
  int oracle = 0;
  for (const auto& r : rows) {
    EXPECT_EQ(r.status, "scored");
    if (r.agent == "oracle") {
      ++oracle;
      EXPECT_TRUE(r.success) << r.task_id << " " << r.detail;
      EXPECT_DOUBLE_EQ(r.ip, 100.0);
    }
  }
  EXPECT_EQ(oracle * 2, static_cast<int>(rows.size()));
  EXPECT_TRUE(fs::exists(fx_.root() / "run" / "bus-0.lcmlog"));
  EXPECT_TRUE(fs::exists(fx_.root() / "run" / "report.html"));
  EXPECT_TRUE(fs::exists(fx_.root() / "run" / "report.png"));
  // mtg report --json: one object with episodes, sr, ip, by_level.
  const std::string out = (fx_.root() / "report.json").string();
  ASSERT_EQ(std::system((testing::bin("mtg") + " report " + (fx_.root() / "run").string() + " --json > " + out).c_str()), 0);
  std::ifstream in(out);
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["episodes"].get<std::size_t>(), rows.size());
  for (const char* key : {"sr", "ip", "by_level"}) EXPECT_TRUE(report.contains(key)) << key;
  // The fixture's three identical boxes make every atomic task Level 2 (no Level 1 exists).
  std::set<std::string> levels;
  for (const auto& r : rows) levels.insert(std::to_string(r.level));
  EXPECT_EQ(levels, (std::set<std::string>{"2", "3"}));
  for (const std::string& level : levels) {
    ASSERT_TRUE(report["by_level"].contains(level)) << level << " in " << report.dump();
    for (const char* key : {"episodes", "sr", "ip", "sr_ci", "ip_ci"}) EXPECT_TRUE(report["by_level"][level].contains(key));
  }
  // What made the run: plan.json's provenance, and one start and one end line in sessions.jsonl.
  std::ifstream plan_in(fx_.root() / "run" / "plan.json");
  const nlohmann::json provenance = nlohmann::json::parse(plan_in).at("provenance");
  EXPECT_FALSE(provenance["mtg_version"].get<std::string>().empty());
  EXPECT_FALSE(provenance["git_revision"].get<std::string>().empty());
  EXPECT_EQ(provenance["command"][1], "run") << provenance.dump();
  EXPECT_NE(provenance["task_set"]["config_hash"], "unknown") << provenance.dump();
  EXPECT_FALSE(provenance["dataset"].empty()) << provenance.dump();
  EXPECT_TRUE(provenance["model_settings"].is_null()) << "built-in agents call no model";
  const nlohmann::json sessions = orchestrator::read_sessions(fx_.root() / "run");
  ASSERT_EQ(sessions.size(), 2u) << sessions.dump();
  EXPECT_EQ(sessions[0]["event"], "start");
  EXPECT_EQ(sessions[0]["resumed"], false);
  EXPECT_EQ(sessions[1]["event"], "end");
  EXPECT_EQ(sessions[1]["ended"], "finished");
  EXPECT_EQ(sessions[1]["episodes_done"].get<std::size_t>(), rows.size());
  // mtg compare: random against oracle (the first agent), checked against a computation from the
  // results themselves: the discordant pairs and the binomial tail summed here term by term.
  const std::string cmp = (fx_.root() / "compare.json").string();
  ASSERT_EQ(std::system((testing::bin("mtg") + " compare " + (fx_.root() / "run").string() + " --json > " + cmp).c_str()), 0);
  std::ifstream cin(cmp);
  const nlohmann::json comparison = nlohmann::json::parse(cin);
  ASSERT_EQ(comparison["comparisons"].size(), 1u);
  const auto& all = comparison["comparisons"][0]["levels"]["all"];
  std::map<std::string, std::pair<bool, bool>> by_task;  // oracle, random
  for (const auto& r : rows) (r.agent == "oracle" ? by_task[r.task_id].first : by_task[r.task_id].second) = r.success;
  int only_oracle = 0, only_random = 0;
  for (const auto& [task, s] : by_task) {
    only_oracle += s.first && !s.second;
    only_random += !s.first && s.second;
  }
  EXPECT_EQ(all["pairs"].get<std::size_t>(), by_task.size());
  EXPECT_EQ(all["only_a"].get<int>(), only_oracle);
  EXPECT_EQ(all["only_b"].get<int>(), only_random);
  const int n = only_oracle + only_random;
  long double term = std::pow(0.5L, n), tail = 0.0L;  // C(n, 0) / 2^n, then C(n, i) / 2^n
  for (int i = 0; i <= std::min(only_oracle, only_random); ++i) {
    tail += term;
    term = term * (n - i) / (i + 1);
  }
  EXPECT_NEAR(all["sr_p"].get<double>(), n == 0 ? 1.0 : std::min(1.0L, 2.0L * tail), 1e-12);
}

TEST_F(RuntimeTest, SameSeedSameResultsAndReplayAndRejudgeReproduceThem) {
  ASSERT_EQ(mtg(run_args("a", {"random"}, 8, 4)), 0) << log_text();
  ASSERT_EQ(mtg(run_args("b", {"random"}, 8, 1)), 0) << log_text();
  const auto a = fingerprints(results("a"));
  EXPECT_EQ(a, fingerprints(results("b")));  // other parallelism, same seed: same verdicts
  ASSERT_EQ(mtg({testing::bin("mtg"), "replay", (fx_.root() / "a").string()}), 0) << log_text();
  EXPECT_EQ(a, fingerprints(results("a/replay")));
  EXPECT_THAT(log_text(), ::testing::HasSubstr("judge results identical"));
  ASSERT_EQ(mtg({testing::bin("mtg"), "rejudge", (fx_.root() / "a").string()}), 0) << log_text();
  EXPECT_EQ(a, fingerprints(orchestrator::read_results(fx_.root() / "a" / "rejudge.sqlite")));
  EXPECT_THAT(log_text(), ::testing::HasSubstr(std::to_string(a.size()) + " identical, 0 differ"));
}

TEST_F(RuntimeTest, KillingTheOrchestratorAndRunningAgainResumesWithoutRunningAnythingTwice) {
  const auto args = run_args("resume", {"oracle"}, 40, 1);
  std::vector<EpisodeRow> before;
  {
    testing::ChildProcess run(args, log());
    ASSERT_TRUE(wait_for_results("resume", 5, 60000)) << log_text();
    run.kill(SIGKILL);
    // The orchestrator inside the run's namespace may store one more result while it stops: what
    // this invocation did is what stands once it let go of the folder.
    for (int i = 0; i < 200 && orchestrator::run_in_progress(fx_.root() / "resume"); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ASSERT_FALSE(orchestrator::run_in_progress(fx_.root() / "resume"));
    before = results("resume");
  }
  ASSERT_GE(before.size(), 5u);
  ASSERT_LT(before.size(), planned("resume"));
  ASSERT_EQ(mtg(args), 0) << log_text();
  const auto after = results("resume");
  EXPECT_EQ(after.size(), planned("resume"));
  const auto first = fingerprints(before);
  const auto all = fingerprints(after);
  for (const auto& [id, fp] : first) EXPECT_EQ(all.at(id), fp) << id;  // finished ones untouched
  for (const auto& r : after) EXPECT_TRUE(r.success) << r.task_id;
  EXPECT_TRUE(fs::exists(fx_.root() / "resume" / "bus-1.lcmlog"));  // a second recording
  // The killed invocation left its start (and, when its orchestrator outlived the kill long
  // enough to stop, an end saying "interrupted"); the resumed one its start, marked as a resume,
  // and its end.
  const nlohmann::json sessions = orchestrator::read_sessions(fx_.root() / "resume");
  ASSERT_GE(sessions.size(), 3u) << sessions.dump(1);
  EXPECT_EQ(sessions.front()["event"], "start");
  EXPECT_EQ(sessions.front()["resumed"], false);
  const nlohmann::json& resumed = sessions[sessions.size() - 2];
  EXPECT_EQ(resumed["event"], "start");
  EXPECT_EQ(resumed["resumed"], true);
  if (sessions.size() == 4) {
    EXPECT_EQ(sessions[1]["ended"], "interrupted") << sessions.dump(1);
  }
  EXPECT_EQ(sessions.back()["event"], "end");
  EXPECT_EQ(sessions.back()["ended"], "finished");
  EXPECT_EQ(sessions.back()["episodes_done"].get<std::size_t>(), planned("resume") - before.size());
}

// `mtg run` runs its orchestrator in a network namespace of its own, as a child process. Killed
// outright (kill -9, the OOM killer), that child cannot say how to go on: the outer `mtg` says it.
TEST_F(RuntimeTest, AKilledInnerOrchestratorStillGetsTheResumeLine) {
  const auto args = run_args("inner", {"oracle"}, 40, 1);
  testing::ChildProcess run(args, log());
  ASSERT_TRUE(wait_for_results("inner", 3, 60000)) << log_text();
  // The inner orchestrator is /proc/self/exe executed again: its name is "exe".
  const pid_t inner = testing::descendant_pid(run.pid(), "exe");
  if (inner <= 0) GTEST_SKIP() << "this run is not isolated (no namespace of its own here)";
  ASSERT_EQ(::kill(inner, SIGKILL), 0);
  EXPECT_EQ(run.wait(60000), 137);
  EXPECT_THAT(log_text(), ::testing::HasSubstr("killed (signal 9, Killed); finished episodes are kept: run the same "
                                               "command again to resume"));
  ASSERT_EQ(mtg(args), 0) << log_text();
  EXPECT_EQ(results("inner").size(), planned("inner"));
}

// An agent that answers differently in each invocation (a person, a model on a cache miss): the
// episodes an interrupted run left unfinished run again as new attempts, so the recording keeps
// both invocations' answers apart and `mtg rejudge` agrees with every stored verdict.
TEST_F(RuntimeTest, AResumedEpisodeRunsAsANewAttemptAndRejudgeAgreesWithEveryVerdict) {
  const fs::path script = fx_.root() / "answers.json";
  // First invocation: keys that exist but are never offered, a step each, up to the step limit.
  std::ofstream(script) << R"({"replies": [)" << [] {
    std::string keys;
    for (int i = 0; i < 40; ++i) keys += std::string(i ? "," : "") + "\"o999\"";
    return keys;
  }() << "]}";
  const auto args = run_args("changing", {"script:" + script.string()}, 0, 2);
  {
    testing::ChildProcess run(args, log());
    ASSERT_TRUE(wait_for_results("changing", 3, 60000)) << log_text();
    ::kill(run.pid(), SIGINT);
    ASSERT_EQ(run.wait(60000), 130) << log_text();
  }
  const std::size_t first_invocation = results("changing").size();
  ASSERT_LT(first_invocation, planned("changing"));
  // Second invocation: the same agent now ends every episode at once.
  std::ofstream(script, std::ios::trunc) << R"({"replies": ["0"]})";
  ASSERT_EQ(mtg(args), 0) << log_text();
  const auto rows = results("changing");
  ASSERT_EQ(rows.size(), planned("changing"));
  int resumed = 0;
  for (const auto& r : rows) {
    if (r.attempt == 0) {
      EXPECT_GT(r.steps, 1) << "a first-invocation episode ran to its step limit";
    } else {
      EXPECT_EQ(r.attempt, 3) << "the second invocation numbers its attempts from max_attempts (3)";
      EXPECT_EQ(r.steps, 1) << r.task_id;
      ++resumed;
    }
  }
  EXPECT_EQ(resumed, static_cast<int>(rows.size() - first_invocation));
  ASSERT_EQ(mtg({testing::bin("mtg"), "rejudge", (fx_.root() / "changing").string()}), 0) << log_text();
  EXPECT_EQ(fingerprints(rows), fingerprints(orchestrator::read_results(fx_.root() / "changing" / "rejudge.sqlite")));
  EXPECT_THAT(log_text(), ::testing::HasSubstr(std::to_string(rows.size()) + " identical, 0 differ"));
}

// A recording damaged in the middle (one event's header overwritten) is read past the damage, and
// what needs the lost event says that the recording is damaged, and where.
TEST_F(RuntimeTest, ADamagedRecordingIsNamedWithTheByteWhereItsDamageStarts) {
  ASSERT_EQ(mtg(run_args("whole", {"oracle"}, 2, 1)), 0) << log_text();
  const fs::path log_file = fx_.root() / "whole" / "bus-0.lcmlog";
  // Where the first agent answer starts, and how many events the file holds.
  long answer_at = -1;
  int events = 0;
  {
    lcm::LogFile in(log_file.string(), "r");
    long at = 0;
    for (const lcm::LogEvent* ev = in.readNextEvent(); ev != nullptr; ev = in.readNextEvent(), ++events) {
      if (answer_at < 0 && bus::is_episode_channel(ev->channel, bus::EpisodeStream::kAction)) answer_at = at;
      at = std::ftell(in.getFilePtr());
    }
  }
  ASSERT_GE(answer_at, 0);
  {
    std::fstream f(log_file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(answer_at);
    f.write("XXXX", 4);  // its sync word
  }
  int read = 0;
  const auto damage = bus::for_each_recorded_event(fx_.root() / "whole", [&](const lcm::LogEvent&) { ++read; });
  // LCM's reader also drops the event before a broken header (it checks the next sync word after
  // each event); the events after the damage are read again.
  EXPECT_GE(read, events - 2) << "every event after the damaged one is still read";
  ASSERT_EQ(damage.size(), 1u);
  EXPECT_LE(damage[0].offset, answer_at);
  EXPECT_GT(damage[0].offset + damage[0].bytes, answer_at);
  EXPECT_FALSE(damage[0].at_end);
  EXPECT_NE(mtg({testing::bin("mtg"), "rejudge", (fx_.root() / "whole").string()}), 0);
  EXPECT_THAT(log_text(), ::testing::HasSubstr("the recording is damaged: bus-0.lcmlog: "));
  EXPECT_THAT(log_text(), ::testing::HasSubstr("at byte " + std::to_string(damage[0].offset)));
  // A text-only run has no image to write: with damage, that is not a silent "wrote 0".
  EXPECT_EQ(mtg({testing::bin("mtg"), "images", (fx_.root() / "whole").string(), "--out",
                 (fx_.root() / "whole-images").string()}),
            1);
  EXPECT_THAT(log_text(), ::testing::HasSubstr("images may have been in what could not be read"));
}

// A recorder that cannot write (here a file-size limit, as a full disk) stops with one line that
// names the file, and leaves the recording whole: what it could not finish is cut off, so no
// torn tail waits for a restarted recorder to repair it. (Before, the run ended with the torn
// event in the file.)
TEST(RecorderTest, AFullDiskLeavesTheRecordingWholeAndSaysSo) {
  testing::FixtureDataset dir;
  const fs::path file = dir.root() / "bus-0.lcmlog";
  const std::string log = (dir.root() / "recorder.log").string();
  // dash's `ulimit -f` counts 512-byte blocks: 96 KiB. SIGXFSZ is left as the shell has it (it
  // kills by default): the recorder itself must take the limit as a full disk.
  testing::ChildProcess recorder({"/bin/sh", "-c", "ulimit -f 192; exec \"$0\" \"$@\"",
                                  testing::bin("mtg_recorder"), "--url", bus::default_url(), "--run", "r",
                                  file.string()},
                                 log);
  bus::Bus bus(bus::default_url());
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!fs::exists(file) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(fs::exists(file));
  int sent = 0;
  bus::HeaderStamper stamp("r", "test:0");
  while (recorder.running() && std::chrono::steady_clock::now() < deadline) {
    // Three unflushed messages, then a result (flushed before it is acknowledged).
    mtg::heartbeat_t beat{};
    beat.header = stamp.next();
    beat.role = std::string(3000, 'b');
    for (int i = 0; i < 3; ++i) bus.publish(bus::kHeartbeat, beat);
    mtg::episode_result_t result{};
    result.header = stamp.next(bus::EpisodeId(sent++), 0, "result");
    result.detail = std::string(2000, 'r');
    bus.publish(bus::kEpisodeResult, result);
    bus.handle_once(5);
  }
  EXPECT_EQ(recorder.wait(5000), 1);
  std::ifstream in(log);
  const std::string said(std::istreambuf_iterator<char>(in), {});
  EXPECT_THAT(said, ::testing::HasSubstr(file.string() + ": cannot write to the recording (File too large; disk full?)"));
  EXPECT_THAT(said, ::testing::HasSubstr("so it is whole up to byte " + std::to_string(fs::file_size(file))));
  EXPECT_GT(fs::file_size(file), 64u * 1024u);
  EXPECT_EQ(bus::whole_events_length(file), fs::file_size(file)) << "a torn event at the end";
  int events = 0;
  EXPECT_TRUE(bus::for_each_recorded_event(dir.root(), [&](const lcm::LogEvent&) { ++events; }).empty());
  EXPECT_GT(events, 10);
}

// A user's mistakes get one line each, exit 1, and spoil nothing: the corrected command then
// runs (or resumes) as if the mistake had never been made.
TEST_F(RuntimeTest, MistakesGetOneLineAndSpoilNothing) {
  auto run_with = [&](const std::string& out, std::vector<std::string> extra,
                      const std::vector<std::string>& agents = {"oracle"}) {
    std::vector<std::string> args = {testing::bin("mtg"), "run", "--tasks", tasks_db_, "--out", (fx_.root() / out).string(),
                                     "--data", fx_.root().string(), "--profile", "none", "--no-progress"};
    for (const auto& a : agents) args.insert(args.end(), {"--agent", a});
    args.insert(args.end(), extra.begin(), extra.end());
    if (std::find(extra.begin(), extra.end(), "--limit") == extra.end()) args.insert(args.end(), {"--limit", "2"});
    const std::size_t before = log_text().size();
    const int status = mtg(args);
    return std::make_pair(status, log_text().substr(before));
  };
  const auto [typo, typo_said] = run_with("typo", {}, {"gpt4"});
  EXPECT_EQ(typo, 1);
  EXPECT_THAT(typo_said, ::testing::HasSubstr("mtg run: unknown agent 'gpt4'"));
  EXPECT_FALSE(fs::exists(fx_.root() / "typo")) << "nothing written for a command that cannot run";
  EXPECT_EQ(run_with("typo", {}).first, 0) << "the corrected command runs in the same folder";
  const auto [no_script, no_script_said] = run_with("script", {}, {"script:" + (fx_.root() / "missing.json").string()});
  EXPECT_EQ(no_script, 1);
  EXPECT_THAT(no_script_said, ::testing::HasSubstr("missing.json"));
  EXPECT_FALSE(fs::exists(fx_.root() / "script")) << "a missing script file is named before the folder is made";
  for (const auto& [option, said] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"--parallel", "0"}, "--parallel must be at least 1"},
           {{"--limit", "-1"}, "--limit must be 0"},
           {{"--image-size", "8192x8192"}, "is outside what an observation may carry"},
           {{"--image-size", "640x48O"}, "--image-size must be WIDTHxHEIGHT"}}) {
    const auto [status, text] = run_with("bad", option);
    EXPECT_EQ(status, 1) << option[0];
    EXPECT_THAT(text, ::testing::HasSubstr(said));
    EXPECT_EQ(text.find("mtg: mtg"), std::string::npos) << "the command is named once: " << text;
  }
  EXPECT_FALSE(fs::exists(fx_.root() / "bad"));
  std::ofstream(fx_.root() / "a_file") << "x";
  const auto [file_out, file_said] = run_with("a_file", {});
  EXPECT_EQ(file_out, 1);
  EXPECT_THAT(file_said, ::testing::HasSubstr("is a file, not a run folder"));
  // A resume with other options that change what is evaluated is refused, naming them.
  const auto [resume, resume_said] = run_with("typo", {"--seed", "9", "--levels", "1"});
  EXPECT_EQ(resume, 1);
  EXPECT_THAT(resume_said, ::testing::HasSubstr("other --levels, --seed"));
  // An episode that is not in the run is named, not silently skipped.
  EXPECT_EQ(mtg({testing::bin("mtg"), "images", (fx_.root() / "typo").string(), "--episode", "99", "--out",
                 (fx_.root() / "images").string()}),
            1);
  EXPECT_THAT(log_text(), ::testing::HasSubstr("episode 99 is not in the recording"));
}

// SIGINT or SIGTERM stops a run cleanly: exit 130, a line that says how to resume, and the same
// command finishes it.
TEST_F(RuntimeTest, AnInterruptedRunSaysSoAndResumes) {
  for (const int sig : {SIGINT, SIGTERM}) {
    const std::string out = sig == SIGINT ? "int" : "term";
    testing::ChildProcess run(run_args(out, {"oracle", "random"}, 0, 2), log());
    ASSERT_TRUE(wait_for_results(out, 10, 60000)) << log_text();
    ::kill(run.pid(), sig);
    EXPECT_EQ(run.wait(60000), 130) << log_text();
    EXPECT_THAT(log_text(), ::testing::HasSubstr("interrupted: run the same command again to resume"));
    EXPECT_EQ(log_text().find("LCM handle failed"), std::string::npos) << log_text();
    ASSERT_EQ(mtg(run_args(out, {"oracle", "random"}, 0, 2)), 0) << log_text();
    EXPECT_EQ(results(out).size(), planned(out));
  }
}

// `--out /dev/null` as root replaced the device with a regular file. Here the real thing, in a
// private mount namespace (a tmpfs over /dev with its own null device), so nothing outside can
// be harmed: `mtg report --html /dev/null` and `mtg scene graph --out /dev/null` are refused with
// one line naming the path, and /dev/null is still the character device afterwards.
TEST_F(RuntimeTest, OutputsNamedDevNullLeaveTheDeviceAlone) {
  if (::geteuid() != 0) GTEST_SKIP() << "a private mount namespace with its own /dev needs root; CI runs as root";
  ASSERT_EQ(mtg(run_args("run", {"oracle"}, 1, 1)), 0) << log_text();
  const std::string inner =
      "mount -t tmpfs tmpfs /dev && mknod -m 666 /dev/null c 1 3 || exit 97; "
      "\"$0\" report \"$1\" --html /dev/null; echo report=$?; "
      "\"$0\" scene graph --data \"$2\" --scene two_tables --profile none --out /dev/null; echo graph=$?; "
      "test -c /dev/null && echo null-is-a-device";
  const int rc = mtg({"/usr/bin/unshare", "-m", "--propagation", "private", "/bin/sh", "-c", inner, testing::bin("mtg"),
                      (fx_.root() / "run").string(), fx_.root().string()});
  if (rc == 97) GTEST_SKIP() << "no tmpfs over /dev in a private mount namespace here: " << log_text();
  const std::string said = log_text();
  EXPECT_THAT(said, ::testing::HasSubstr("report=1"));
  EXPECT_THAT(said, ::testing::HasSubstr("graph=1"));
  EXPECT_THAT(said, ::testing::HasSubstr("/dev/null: is a character device; give the path of a file to write"));
  EXPECT_THAT(said, ::testing::HasSubstr("null-is-a-device"));
}

// A judge stopped with SIGSTOP (hung: alive, silent) once the run is under way. Before, nobody
// noticed: its attempts timed out three times and were given up, lost for good. Now its missing
// heartbeats get it killed within the episode time-out and restarted, and every episode is
// scored as in a run nobody disturbed.
TEST_F(RuntimeTest, AHungServiceIsKilledAndRestartedAndNoEpisodeIsLost) {
  ASSERT_EQ(mtg(run_args("calm", {"oracle"}, 12, 2)), 0) << log_text();
  std::map<std::int64_t, std::string> calm;
  for (const auto& r : results("calm")) calm[r.episode_id.value()] = orchestrator::verdict_fingerprint(r);
  testing::ChildProcess run(run_args("hung", {"oracle"}, 12, 2), log());
  ASSERT_TRUE(wait_for_results("hung", 2, 60000)) << log_text();
  const pid_t judge = testing::descendant_pid(run.pid(), "mtg_judge");
  ASSERT_GT(judge, 0) << "no mtg_judge under the run";
  ASSERT_EQ(::kill(judge, SIGSTOP), 0);
  ASSERT_EQ(run.wait(120000), 0) << log_text();
  std::map<std::int64_t, std::string> hung;
  for (const auto& r : results("hung")) {
    EXPECT_EQ(r.status, "scored") << r.task_id << ": " << r.detail;
    hung[r.episode_id.value()] = orchestrator::verdict_fingerprint(r);
  }
  EXPECT_EQ(hung.size(), planned("hung"));
  // Attempt numbers differ where an attempt was retried; the verdicts do not.
  EXPECT_EQ(hung, calm);
  EXPECT_THAT(log_text(), ::testing::HasSubstr("judge (pid " + std::to_string(judge) + ") sent no heartbeat"));
  ::kill(judge, SIGKILL);  // had it survived, it is not left behind stopped
}

TEST_F(RuntimeTest, ASlowServiceIsLeftAloneWhileItWorks) {
  // The judge works 17.5 s without a heartbeat (past the 16 s after which a silent service that does
  // no work is taken for hung, within the 20 s episode time-out): it is slow, not hung, and keeps
  // its pid; the run's verdicts are those of a calm run.
  auto args = run_args("slow", {"oracle"}, 4, 2);
  args[std::distance(args.begin(), std::find(args.begin(), args.end(), "--episode-timeout")) + 1] = "20";
  ASSERT_EQ(mtg(run_args("calm", {"oracle"}, 4, 2)), 0) << log_text();
  std::map<std::int64_t, std::string> calm;
  for (const auto& r : results("calm")) calm[r.episode_id.value()] = orchestrator::verdict_fingerprint(r);
  const fs::path marks = fx_.root() / "slow-marks";
  fs::create_directories(marks);
  ::setenv("MTG_FAULTS", "judge_busy:17500", 1);
  ::setenv("MTG_FAULT_MARKS", marks.c_str(), 1);
  testing::ChildProcess run(args, log());
  ::unsetenv("MTG_FAULTS");
  ::unsetenv("MTG_FAULT_MARKS");
  pid_t judge = 0;
  for (int i = 0; i < 600 && judge <= 0; ++i) {
    judge = testing::descendant_pid(run.pid(), "mtg_judge");
    if (judge <= 0) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_GT(judge, 0) << "no mtg_judge under the run";
  ASSERT_EQ(run.wait(120000), 0) << log_text();
  ASSERT_TRUE(fs::exists(marks / "judge_busy")) << "the fault did not happen: " << log_text();
  std::map<std::int64_t, std::string> slow;
  for (const auto& r : results("slow")) {
    EXPECT_EQ(r.status, "scored") << r.task_id << ": " << r.detail;
    slow[r.episode_id.value()] = orchestrator::verdict_fingerprint(r);
  }
  EXPECT_EQ(slow, calm);
  const std::string text = log_text();
  EXPECT_THAT(text, ::testing::HasSubstr("judge (pid " + std::to_string(judge) + ") sent no heartbeat"));
  EXPECT_THAT(text, ::testing::HasSubstr("slow, not hung"));
  EXPECT_THAT(text, ::testing::Not(::testing::HasSubstr("it hangs")));
  EXPECT_THAT(text, ::testing::Not(::testing::HasSubstr("restarting it")));
}

// Kills one service (found in the run's process tree) once the run is under way.
class KillServiceTest : public RuntimeTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(KillServiceTest, TheOrchestratorRestartsItAndRetriesItsEpisodes) {
  const std::string role = GetParam();
  const std::map<std::string, std::string> program = {
      {"scene_graph", "mtg_scene_graph"}, {"judge", "mtg_judge"}, {"agent:oracle", "mtg_agent"}, {"recorder", "mtg_recorder"}};
  testing::ChildProcess run(run_args("kill", {"oracle"}, 40, 2), log());
  ASSERT_TRUE(wait_for_results("kill", 5, 60000)) << log_text();
  const pid_t victim = testing::descendant_pid(run.pid(), program.at(role));
  ASSERT_GT(victim, 0) << "no " << program.at(role) << " under the run";
  ASSERT_EQ(::kill(victim, SIGKILL), 0);
  ASSERT_EQ(run.wait(120000), 0) << log_text();
  const auto rows = results("kill");
  EXPECT_EQ(rows.size(), planned("kill"));
  for (const auto& r : rows) {
    EXPECT_EQ(r.status, "scored") << r.task_id << ": " << r.detail;
    EXPECT_TRUE(r.success) << r.task_id << ": " << r.detail;
  }
  EXPECT_THAT(log_text(), ::testing::HasSubstr("restarting it"));
}

INSTANTIATE_TEST_SUITE_P(EachService, KillServiceTest,
                         ::testing::Values("scene_graph", "judge", "agent:oracle", "recorder"),
                         [](const auto& p) {
                           std::string n = p.param;
                           for (auto& c : n) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return n;
                         });

TEST_F(RuntimeTest, ALostStateUpdateIsDetectedAndTheEpisodeRetried) {
  ::setenv("MTG_FAULTS", "drop_state:2", 1);
  const int status = mtg(run_args("drop", {"oracle"}, 4, 2));
  ::unsetenv("MTG_FAULTS");
  ASSERT_EQ(status, 0) << log_text();
  const auto rows = results("drop");
  ASSERT_EQ(rows.size(), planned("drop"));
  for (const auto& r : rows) {
    EXPECT_TRUE(r.success) << r.detail;  // never mis-scored
    EXPECT_EQ(r.attempt, 1);             // the first attempt lost a message and was retried
  }
  EXPECT_THAT(log_text(), ::testing::HasSubstr("lost state update"));
}

TEST_F(RuntimeTest, ADuplicatedStateUpdateIsIgnored) {
  ::setenv("MTG_FAULTS", "dup_state:2", 1);
  const int status = mtg(run_args("dup", {"oracle"}, 4, 2));
  ::unsetenv("MTG_FAULTS");
  ASSERT_EQ(status, 0) << log_text();
  for (const auto& r : results("dup")) {
    EXPECT_TRUE(r.success) << r.detail;
    EXPECT_EQ(r.attempt, 0);
  }
}

TEST_F(RuntimeTest, MalformedRepliesCostAStepEachAndCrashNothing) {
  const std::string script = (fx_.root() / "script.json").string();
  std::ofstream(script) << nlohmann::json{{"replies", {"garbage !!!", "", std::string(100000, 'x'), "l99", "o7", "0"}}}.dump();
  ASSERT_EQ(mtg(run_args("bad", {"script:" + script}, 2, 2)), 0) << log_text();
  const auto rows = results("bad");
  ASSERT_EQ(rows.size(), planned("bad"));
  for (const auto& r : rows) {
    EXPECT_EQ(r.status, "scored");
    EXPECT_EQ(r.steps, 6);
    EXPECT_EQ(r.invalid_actions, 5);
    EXPECT_FALSE(r.success);
  }
}

TEST_F(RuntimeTest, ATaskThatCannotRunIsRefusedBeforeTheRunStarts) {
  // A task of a scene the data does not have, and one whose goal names an object its scene lacks:
  // each is refused with one line naming the task, before anything is written (before: every
  // episode of it was given up as an error row, after the run had started).
  tasks::Task t;
  t.id = "nowhere/L1/000000";
  t.scene = "nowhere";
  t.level = 1;
  t.type = "surface";
  t.text = "Move the box.";
  t.goal = {{"atomic", {{"type", "surface"}, {"item", "box_1"}, {"source", "x"}, {"platform", "y"}}}};
  t.oracle = {"0"};
  tasks::TaskSet set;
  set.scene = "nowhere";
  set.tasks = {t};
  const std::string good_db = tasks_db_;
  tasks_db_ = (fx_.root() / "bad_tasks.sqlite").string();
  tasks::write_task_db(tasks_db_, {set}, {}, tasks::TaskOptions{});
  ASSERT_EQ(mtg(run_args("nowhere", {"oracle"}, 0, 1), 60000), 1) << log_text();
  EXPECT_THAT(log_text(), ::testing::HasSubstr("unknown scene 'nowhere'"));
  EXPECT_FALSE(fs::exists(fx_.root() / "nowhere" / "results.sqlite"));

  auto tasks = tasks::read_tasks(good_db);
  ASSERT_FALSE(tasks.empty());
  tasks::TaskSet broken;
  broken.scene = tasks.front().scene;
  tasks.front().goal["atomic"]["item"] = "no_such_object_9";
  broken.tasks = {tasks.front()};
  tasks_db_ = (fx_.root() / "broken_goal.sqlite").string();
  tasks::write_task_db(tasks_db_, {broken}, {}, tasks::TaskOptions{});
  ASSERT_EQ(mtg(run_args("broken", {"oracle"}, 0, 1), 60000), 1) << log_text();
  EXPECT_THAT(log_text(), ::testing::HasSubstr("task " + tasks.front().id + ": its goal does not hold in scene"));
  EXPECT_FALSE(fs::exists(fx_.root() / "broken" / "results.sqlite"));
}

TEST_F(RuntimeTest, LcmLogplayerOntoABusWithAJudgeGivesTheSameResults) {
  ASSERT_EQ(mtg(run_args("played", {"random"}, 5, 2)), 0) << log_text();
  const auto recorded = results("played");
  bus::Bus bus(bus::kDefaultUrl);
  // The recorded answers are sealed: the judge opens them with the run folder's key.
  testing::ChildProcess judge({testing::bin("mtg_judge"), "--profile", "none", "--truth-key-file",
                               (fx_.root() / "played" / "truth.key").string()},
                              log());
  const std::string prefix = "judge:";
  std::map<std::int64_t, mtg::episode_result_t> fresh;
  bool ready = false;
  bus.subscribe<mtg::heartbeat_t>(bus::kHeartbeat, [&](const std::string&, const mtg::heartbeat_t& m) {
    ready = ready || m.pid == judge.pid();
  });
  bus.subscribe<mtg::episode_result_t>(bus::kEpisodeResult, [&](const std::string&, const mtg::episode_result_t& m) {
    if (m.header.sender.find(":" + std::to_string(judge.pid())) != std::string::npos) fresh[m.header.episode_id] = m;
  });
  ASSERT_TRUE(bus.handle_until([&] { return ready; }, 10000));
  // The stock player, only the channels a judge listens to, as fast as it goes.
  testing::ChildProcess player({"/usr/bin/lcm-logplayer", "-s", "20", "-e", "^MTG_(EPISODE_START|EPISODE_TRUTH|STATE|ACT)$",
                                (fx_.root() / "played" / "bus-0.lcmlog").string()},
                               log());
  ASSERT_TRUE(bus.handle_until([&] { return fresh.size() == recorded.size(); }, 30000)) << fresh.size();
  for (const auto& r : recorded) {
    const auto& m = fresh.at(r.episode_id.value());
    EXPECT_EQ(m.success != 0, r.success);
    EXPECT_DOUBLE_EQ(m.ip, r.ip);
    EXPECT_EQ(m.cause, r.cause);
    EXPECT_EQ(m.stage, r.stage);
    EXPECT_EQ(m.steps, r.steps);
  }
}


// The whole runtime on a real apartment: tasks of all four levels from apt_0, then the oracle
// and the random agent over the bus, several episodes in flight.
TEST(ShippedRuntime, OracleSolvesEveryLevelOfApt0AndRandomRunsToAVerdict) {
  MTG_REQUIRE_SHIPPED_DATA();
  testing::FixtureDataset scratch;
  const fs::path dir = scratch.root();
  const std::string log = (dir / "mtg.log").string();
  const std::string db = (dir / "apt_0.sqlite").string();
  ASSERT_EQ(testing::ChildProcess({testing::bin("mtg"), "tasks", "--scene", "apt_0", "--levels", "1,2,3,4",
                                   "--l3-count", "50", "--out", db},
                                  log)
                .wait(300000),
            0);
  ASSERT_EQ(testing::ChildProcess({testing::bin("mtg"), "run", "--tasks", db, "--levels", "1,2,3,4", "--limit", "4",
                                   "--parallel", "4", "--agent", "oracle", "--agent", "random", "--out",
                                   (dir / "run").string(), "--no-progress"},
                                  log)
                .wait(300000),
            0);
  const auto rows = orchestrator::read_results(dir / "run" / "results.sqlite");
  ASSERT_EQ(rows.size(), 32u);  // 4 per level and agent
  std::map<std::string, int> step_limit;  // a Level 3 or 4 plan may need more than 15 steps
  for (const tasks::Task& t : tasks::read_tasks(db)) step_limit[t.id] = t.step_limit;
  std::set<int> levels;
  for (const auto& r : rows) {
    EXPECT_EQ(r.status, "scored") << r.task_id << ": " << r.detail;
    levels.insert(r.level);
    if (r.agent == "oracle") {
      EXPECT_TRUE(r.success) << r.task_id << ": " << r.detail;
      EXPECT_DOUBLE_EQ(r.ip, 100.0) << r.task_id;
    } else {
      EXPECT_LE(r.steps, step_limit.at(r.task_id)) << r.task_id;
      if (!r.success) {
        EXPECT_FALSE(r.cause.empty()) << r.task_id;
      }
    }
  }
  EXPECT_EQ(levels, (std::set<int>{1, 2, 3, 4}));
}

}  // namespace
}  // namespace mtg
