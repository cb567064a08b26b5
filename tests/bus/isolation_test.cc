// Runs nobody can spoil (docs/runtime.md, "Isolation" and "Recording"): ten runs at once in
// folders of the same name give exactly what each gives alone; datagrams forged from outside a
// run never reach it; a recorder killed three times leaves logs the stock lcm-logplayer plays to
// their end and `mtg rejudge` finds every episode in; agents never receive a goal or a plan.

#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <set>

#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/recording.h"
#include "bus/url.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_result_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"
#include "mtg/observation_t.hpp"
#include "mtg/run_control_t.hpp"
#include "orchestrator/run/rejudge.h"
#include "orchestrator/run/run_plan.h"
#include "tests/support/run_fixture.h"

namespace mtg {
namespace {

namespace fs = std::filesystem;
using IsolationTest = testing::RunFixture;

// One LCM datagram (the small-message form of lcm/lcm_udpm.c: magic "LC02", sequence number,
// channel, NUL, message) to 127.0.0.1:7667, as a process that is not on the bus could send it.
void send_unicast(const std::string& channel, const std::vector<std::uint8_t>& message) {
  std::vector<std::uint8_t> packet = {'L', 'C', '0', '2', 0, 0, 0, 0};
  packet.insert(packet.end(), channel.begin(), channel.end());
  packet.push_back(0);
  packet.insert(packet.end(), message.begin(), message.end());
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(7667);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  (void)::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof(to));
  ::close(fd);
}

// Two runs at once in folders of the same name, eight more beside them: every one gives, episode
// for episode, the verdicts of the same run made alone, and each has its own run id.
TEST_F(IsolationTest, TenRunsAtOnceGiveExactlyWhatEachGivesAlone) {
  ASSERT_EQ(mtg(run_args("alone/run", {"oracle", "random"}, 6, 2)), 0) << log_text();
  const auto alone = fingerprints(results("alone/run"));
  std::vector<std::unique_ptr<testing::ChildProcess>> runs;
  for (int i = 0; i < 10; ++i) {
    const std::string out = "many" + std::to_string(i) + "/run";  // the same folder name, ten times
    runs.push_back(std::make_unique<testing::ChildProcess>(run_args(out, {"oracle", "random"}, 6, 2), log()));
  }
  std::set<std::string> ids;
  for (int i = 0; i < 10; ++i) {
    const std::string out = "many" + std::to_string(i) + "/run";
    ASSERT_EQ(runs[static_cast<std::size_t>(i)]->wait(180000), 0) << log_text();
    EXPECT_EQ(fingerprints(results(out)), alone) << out;
    ids.insert(orchestrator::load_plan(fx_.root() / out).run_id);
  }
  EXPECT_EQ(ids.size(), 10u) << "every run has an identity of its own";
}

// While a run is under way, this test's own bus (another network namespace than the run's)
// carries a forged result of every episode and a shutdown, by multicast and to 127.0.0.1: none
// of it reaches the run, whose results and recording are those of the same run made alone.
TEST_F(IsolationTest, DatagramsForgedOutsideARunNeverReachIt) {
  ASSERT_EQ(mtg(run_args("alone", {"random"}, 40, 2)), 0) << log_text();
  const auto alone = fingerprints(results("alone"));
  testing::ChildProcess run(run_args("target", {"random"}, 40, 2), log());
  ASSERT_TRUE(wait_for_results("target", 1, 60000)) << log_text();
  const std::string run_id = orchestrator::load_plan(fx_.root() / "target").run_id;
  bus::Bus multicast(bus::kDefaultUrl);
  auto forge = [&](auto msg, const std::string& channel) {
    msg.header.run_id = run_id;
    msg.header.sender = "forger:0";
    multicast.publish(channel, msg);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    send_unicast(channel, bytes);  // straight to the port every run's bus listens on
  };
  for (std::int64_t id = 0; id < 40 && run.running(); ++id) {
    mtg::episode_result_t fake{};
    fake.header.episode_id = id;
    fake.success = true;
    fake.ip = 100.0;
    fake.stage = "done";
    forge(fake, bus::kEpisodeResult);
  }
  mtg::run_control_t stop{};
  stop.command = "shutdown";
  forge(stop, bus::kControl);
  ASSERT_EQ(run.wait(120000), 0) << log_text();
  EXPECT_EQ(fingerprints(results("target")), alone);
  int forged = 0;
  bus::for_each_recorded_event(fx_.root() / "target", [&](const lcm::LogEvent& ev) {
    const std::string bytes(static_cast<const char*>(ev.data), static_cast<std::size_t>(ev.datalen));
    forged += bytes.find("forger:0") != std::string::npos ? 1 : 0;
  });
  EXPECT_EQ(forged, 0);
}

// kill -9 of the recorder three times during a run: each restart cuts its predecessor's torn
// last event off before appending, episodes it never acknowledged run again, and in the end the
// stock lcm-logplayer plays every event of the log and `mtg rejudge` finds every episode.
TEST_F(IsolationTest, ARecorderKilledThreeTimesLeavesAWholeRecording) {
  testing::ChildProcess run(run_args("killed", {"oracle", "random"}, 0, 2), log());
  pid_t last = -1;
  for (std::size_t k = 1; k <= 3; ++k) {
    ASSERT_TRUE(wait_for_results("killed", 40 * k, 120000)) << log_text();
    pid_t recorder = -1;
    for (int i = 0; i < 200 && (recorder <= 0 || recorder == last); ++i) {
      recorder = testing::descendant_pid(run.pid(), "mtg_recorder");
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_GT(recorder, 0);
    ASSERT_NE(recorder, last) << "the recorder was restarted";
    ASSERT_EQ(::kill(recorder, SIGKILL), 0);
    last = recorder;
  }
  ASSERT_EQ(run.wait(300000), 0) << log_text();
  const auto rows = results("killed");
  ASSERT_EQ(rows.size(), planned("killed"));
  // Every event of the log, read by LCM's own reader, is played by the stock player.
  const fs::path log_file = fx_.root() / "killed" / "bus-0.lcmlog";
  std::int64_t events = 0;
  {
    lcm::LogFile file(log_file.string(), "r");
    while (file.readNextEvent() != nullptr) ++events;
  }
  bus::Bus bus(bus::kDefaultUrl);
  std::int64_t played = 0;
  bus.subscribe_raw(".*", [&](const std::string&, std::span<const std::uint8_t>, std::int64_t) { ++played; });
  testing::ChildProcess player({"/usr/bin/lcm-logplayer", "-s", "50", log_file.string()}, log());
  bus.handle_until([&] { return played >= events; }, 120000);
  EXPECT_EQ(played, events);
  EXPECT_GT(events, 1000);
  std::ifstream recorder_log(fx_.root() / "killed" / "logs" / "recorder.log");
  const std::string said(std::istreambuf_iterator<char>(recorder_log), {});
  int torn = 0;
  for (auto at = said.find("torn last event"); at != std::string::npos; at = said.find("torn last event", at + 1)) ++torn;
  std::printf("[ recorder ] %zu episodes, %lld of %lld events played, %d torn events cut off\n", rows.size(),
              static_cast<long long>(played), static_cast<long long>(events), torn);
  // And re-judging the recording finds every stored episode, with the same verdict.
  const auto again = orchestrator::rejudge_run(fx_.root() / "killed");
  EXPECT_EQ(again.identical, static_cast<std::int64_t>(rows.size()));
}

// An agent subscribes to episode starts and observations: nothing it receives holds a goal or
// an oracle plan (they travel on MTG_EPISODE_TRUTH, for the judge, the scene-graph service and
// the oracle only), while the oracle still solves every task. A listener on that channel too
// (any process on a shared bus) gets only sealed answers; the run folder's key opens them.
TEST_F(IsolationTest, AgentsAndListenersNeverReadTheAnswers) {
  bus::Bus bus(bus::kDefaultUrl);
  int starts = 0, observations = 0;
  std::vector<mtg::episode_truth_t> overheard;
  std::vector<std::string> leaks;
  auto inspect = [&](const std::string& channel, std::span<const std::uint8_t> bytes) {
    const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    // Goal JSON, and the instance names only goals and plans use (texts say "the leftmost box").
    for (const char* answer : {"\"atomic\"", "\"sequence\"", "\"item\":", "box_1", "box_2", "box_3"}) {
      if (text.find(answer) != std::string::npos) leaks.push_back(channel + " holds " + answer);
    }
  };
  bus.subscribe_raw(bus::kEpisodeStart, [&](const std::string& c, std::span<const std::uint8_t> b, std::int64_t) {
    ++starts;
    inspect(c, b);
  });
  bus.subscribe_raw(bus::episode_channel(bus::EpisodeStream::kObservation),
                    [&](const std::string& c, std::span<const std::uint8_t> b, std::int64_t) {
                      ++observations;
                      inspect(c, b);
                    });
  bus.subscribe_raw(bus::kEpisodeTruth, [&](const std::string& c, std::span<const std::uint8_t> b, std::int64_t) {
    inspect(c, b);
    mtg::episode_truth_t t{};
    if (t.decode(b.data(), 0, static_cast<int>(b.size())) >= 0) overheard.push_back(t);
  });
  // On this test's bus, so the test can listen as an agent would.
  auto args = run_args("watched", {"oracle"}, 6, 2);
  args.insert(args.end(), {"--bus", bus::kDefaultUrl});
  testing::ChildProcess run(args, log());
  while (run.running()) bus.handle_once(20);
  while (bus.handle_once(50)) {
  }
  EXPECT_EQ(run.wait(1000), 0) << log_text();
  const auto rows = results("watched");
  for (const auto& r : rows) EXPECT_TRUE(r.success) << r.task_id << ": " << r.detail;
  EXPECT_EQ(starts, static_cast<int>(rows.size()));
  EXPECT_GT(observations, starts);
  EXPECT_THAT(leaks, ::testing::IsEmpty());
  ASSERT_EQ(overheard.size(), rows.size());
  const bus::RecordedTruths answers(fx_.root() / "watched");
  for (const auto& t : overheard) {
    EXPECT_TRUE(bus::is_sealed(t));
    EXPECT_TRUE(t.goal_json.empty() && t.oracle_plan.empty() && t.identify_json.empty());
    const auto opened = answers.open(t);
    EXPECT_NE(opened.goal_json.find("\"item\""), std::string::npos) << opened.goal_json;
    EXPECT_FALSE(opened.oracle_plan.empty());
    // Bound to its episode: passed off as another's, it does not open.
    auto moved = t;
    moved.header.episode_id += 1;
    EXPECT_THROW(answers.open(moved), Error);
  }
  // Whoever holds the run folder reads them: rejudge and the viewer.
  const auto again = orchestrator::rejudge_run(fx_.root() / "watched");
  EXPECT_EQ(again.identical, static_cast<std::int64_t>(rows.size()));
  fs::remove(fx_.root() / "watched" / bus::TruthSeal::kFileName);
  try {
    orchestrator::rejudge_run(fx_.root() / "watched");
    ADD_FAILURE() << "rejudge without the key";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("truth.key is missing"));
  }
}

}  // namespace
}  // namespace mtg
