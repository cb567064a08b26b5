// LocalRuntime's bookkeeping of an attempt's end, on an in-process bus (memq://, no processes):
// the judge's result and the recorder's acknowledgement come from two senders, and the bus keeps
// no order across senders, so either may come first.

#include "orchestrator/run/local_runtime.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include "bus/channels.h"
#include "bus/header.h"
#include "mtg/recorded_t.hpp"

namespace mtg::orchestrator {
namespace {

struct Collected final : LaunchSink {
  void on_result(const mtg::episode_result_t& r, const std::string&, const bus::RecordingRef*) override { results.push_back(r.header.episode_id); }
  void on_failure(bus::EpisodeId id, int, const std::string&) override { failures.push_back(id.value()); }
  void on_agent_stopped(const std::string&, const std::string&) override {}
  std::vector<std::int64_t> results, failures;
};

class AttemptEnd : public ::testing::Test {
 protected:
  AttemptEnd() : runtime_(config(), dir_) {}
  ~AttemptEnd() override { std::filesystem::remove_all(dir_); }

  static RuntimeConfig config() {
    RuntimeConfig c;
    c.run_id = "run";
    c.bus_url = "memq://";
    c.recorder = "mtg";  // acknowledges every result it writes
    return c;
  }
  static mtg::header_t header(std::int64_t episode, int attempt) {
    mtg::header_t h{};
    h.run_id = "run";
    h.episode_id = episode;
    h.attempt = attempt;
    h.sender = "test";
    h.schema_version = bus::kSchemaVersion;
    return h;
  }
  void launch(std::int64_t episode) {
    EpisodeLaunch l{};
    l.start.header = header(episode, 0);
    l.truth.header = header(episode, 0);
    runtime_.launch(l);
  }
  void result(std::int64_t episode, int attempt = 0) {
    mtg::episode_result_t m{};
    m.header = header(episode, attempt);
    runtime_.bus().publish(bus::kEpisodeResult, m);
  }
  void recorded(std::int64_t episode, int attempt = 0) {
    mtg::recorded_t m{};
    m.header = header(episode, attempt);
    runtime_.bus().publish(bus::kRecorded, m);
  }
  std::vector<std::int64_t> poll() {
    Collected sink;
    for (int i = 0; i < 5; ++i) runtime_.poll(10, sink);
    EXPECT_TRUE(sink.failures.empty());
    return sink.results;
  }

  const std::filesystem::path dir_ =
      std::filesystem::temp_directory_path() / ("mtg_local_runtime_test_" + std::to_string(::getpid()));
  LocalRuntime runtime_;
};

TEST_F(AttemptEnd, TheResultIsStoredOnceTheRecorderHasIt) {
  launch(1);
  result(1);
  EXPECT_TRUE(poll().empty()) << "not before the recording holds it";
  recorded(1);
  EXPECT_EQ(poll(), std::vector<std::int64_t>{1});
  EXPECT_EQ(runtime_.in_flight(), 0);
}

TEST_F(AttemptEnd, AnAcknowledgementThatOvertakesTheResultStillCounts) {
  launch(2);
  recorded(2);
  EXPECT_TRUE(poll().empty());
  result(2);
  EXPECT_EQ(poll(), std::vector<std::int64_t>{2}) << "stored when the result comes, not after the time-out";
  result(2);
  recorded(2);
  EXPECT_TRUE(poll().empty()) << "a repeated result or acknowledgement stores nothing more";
}

TEST_F(AttemptEnd, AnotherAttemptsAcknowledgementDoesNotCount) {
  launch(3);
  recorded(3, /*attempt=*/1);
  result(3);
  EXPECT_TRUE(poll().empty());
  recorded(3);
  EXPECT_EQ(poll(), std::vector<std::int64_t>{3});
}

}  // namespace
}  // namespace mtg::orchestrator
