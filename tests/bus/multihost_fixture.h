#pragma once
// The simulated hosts of the multi-host and cluster tests: network namespaces joined by veth
// pairs to a bridge (scripts/netns-hosts), each running `mtg worker`; the coordinator runs in the
// test's own namespace. The hosts are made and removed here, with a task set on a fixture scene.

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <set>
#include <thread>

#include <nlohmann/json.hpp>

#include "bus/recording.h"
#include "bus/channels.h"
#include "core/scene/dataset_fingerprint.h"
#include "core/store/sqlite.h"
#include "core/tasks/generator.h"
#include "core/tasks/task_db.h"
#include "mtg/episode_start_t.hpp"
#include "orchestrator/remote/lease_book.h"
#include "orchestrator/run/results_db.h"
#include "tests/support/fixture_dataset.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/process.h"
#include "tests/support/text_file.h"

namespace mtg {
namespace testing_multihost {

namespace fs = std::filesystem;
using orchestrator::EpisodeRow;

constexpr const char* kSharedUrl = "udpm://239.255.77.1:7701?ttl=1";  // the hosts' multicast group

using testing::read_text;

inline std::string script(const std::string& name) { return (fs::path(MTG_SOURCE_DIR) / "scripts" / name).string(); }

class MultiHostTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // `ip netns add` needs real root; scripts/with-bus runs non-root users in a user namespace.
    std::ifstream map("/proc/self/uid_map");
    std::string inside, outside;
    map >> inside >> outside;
    if (outside != "0") GTEST_SKIP() << "simulated hosts need root (ip netns); CI runs as root";
    // The shared bus is authenticated: every host of the test reads the same key file.
    const auto key = fx_.root() / "bus.key";
    std::ofstream(key) << "test-secret-of-the-multihost-fixture\n";
    ::setenv("MTG_BUS_KEY", key.c_str(), 1);
    built_ = testing::two_tables(fx_);
    tasks::TaskOptions options;
    options.level3_count = 40;
    options.levels = {1, 2, 3};
    auto generated = tasks::generate_tasks(built_.scene, built_.graph, options);
    // As `mtg tasks` does: the task set remembers the files its scene was made from.
    generated.set.dataset = scene::fingerprint_files(fx_.root(), built_.scene.source_files);
    tasks_db_ = (fx_.root() / "tasks.sqlite").string();
    tasks::write_task_db(tasks_db_, {generated.set}, generated.votes, options);
    prefix_ = "h" + std::to_string(::getpid() % 100000);
  }

  void TearDown() override {
    workers_.clear();
    if (hosts_ > 0) sh({script("netns-hosts"), "down", prefix_, std::to_string(hosts_)});
  }

  int sh(const std::vector<std::string>& argv) {
    testing::ChildProcess p(argv, log());
    return p.wait(60000);
  }

  void make_hosts(int n) {
    ASSERT_EQ(sh({script("netns-hosts"), "up", prefix_, std::to_string(n)}), 0) << log_text();
    hosts_ = n;
  }

  std::string host(int i) const { return prefix_ + std::to_string(i); }

  /// With `uid` >= 0 the worker runs as that user (and group), owning its --dir.
  void start_worker(int i, int capacity = 2, const std::vector<std::string>& extra = {}, int uid = -1) {
    const fs::path dir = fx_.root() / ("worker" + std::to_string(i));
    std::vector<std::string> argv = {script("netns-hosts"), "exec", host(i)};
    if (uid >= 0) {
      fs::create_directories(dir);
      ASSERT_EQ(::chown(dir.c_str(), static_cast<uid_t>(uid), static_cast<gid_t>(uid)), 0) << dir;
      argv.insert(argv.end(), {"/usr/bin/setpriv", "--reuid=" + std::to_string(uid), "--regid=" + std::to_string(uid),
                               "--clear-groups"});
    }
    argv.insert(argv.end(), {testing::bin("mtg"), "worker", "--bus", shared_url_, "--name", "host" + std::to_string(i),
                             "--capacity", std::to_string(capacity), "--dir", dir.string()});
    argv.insert(argv.end(), extra.begin(), extra.end());
    workers_[i] = std::make_unique<testing::ChildProcess>(argv, (fx_.root() / ("worker" + std::to_string(i) + ".log")).string());
  }

  // Kills every process of host i at once, as a power cut would.
  void kill_host(int i) {
    ASSERT_EQ(sh({"/bin/sh", "-c", "kill -9 $(ip netns pids " + host(i) + ")"}), 0) << log_text();
    workers_.erase(i);
  }

  std::vector<std::string> run_args(const std::string& out, int limit, int parallel, int min_workers) {
    std::vector<std::string> args = {testing::bin("mtg"), "run", "--tasks", tasks_db_, "--levels", "1,2,3", "--limit",
                                     std::to_string(limit), "--parallel", std::to_string(parallel), "--out",
                                     (fx_.root() / out).string(), "--data", fx_.root().string(), "--profile", "none",
                                     "--episode-timeout", "10", "--no-progress", "--agent", "oracle", "--agent",
                                     "random", "--seed", "7"};
    if (min_workers > 0) {
      args.insert(args.end(), {"--remote", "--bus", shared_url_, "--lease-ttl", "2", "--min-workers"});
      args.push_back(std::to_string(min_workers));
    }
    return args;
  }

  int mtg(const std::vector<std::string>& args, int timeout_ms = 180000) {
    testing::ChildProcess p(args, log());
    return p.wait(timeout_ms);
  }

  std::string log() const { return (fx_.root() / "mtg.log").string(); }
  std::string log_text() const {
    std::string all;
    for (const auto& entry : fs::directory_iterator(fx_.root())) {
      if (entry.path().extension() == ".log") all += "== " + entry.path().filename().string() + "\n" + read_text(entry.path());
    }
    return all;
  }

  std::vector<EpisodeRow> results(const std::string& out) {
    return orchestrator::read_results(fx_.root() / out / "results.sqlite");
  }

  std::size_t planned(const std::string& out) {
    std::ifstream in(fx_.root() / out / "plan.json");
    return nlohmann::json::parse(in)["episodes"].size();
  }

  bool wait_for(const std::function<bool()>& done, int timeout_ms) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (std::chrono::steady_clock::now() < deadline) {
      try {
        if (done()) return true;
      } catch (const std::exception&) {
        // a database still being created
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  // Leases the coordinator has out, per worker sender id (leases.sqlite).
  std::map<std::string, int> open_leases(const std::string& out) {
    return leases_in_state(out, orchestrator::remote::LeaseState::kGranted);
  }

  // Leases the coordinator's book holds in one state, per worker sender id.
  std::map<std::string, int> leases_in_state(const std::string& out, orchestrator::remote::LeaseState state) {
    store::Database db(fx_.root() / out / "leases.sqlite", store::Database::Mode::kReadOnly);
    store::Statement q(db, "SELECT worker, COUNT(*) FROM leases WHERE state = ? GROUP BY worker");
    q.bind(1, orchestrator::remote::to_string(state));
    std::map<std::string, int> n;
    while (q.step()) n[q.column_text(0)] = static_cast<int>(q.column_int(1));
    return n;
  }

  static std::map<std::int64_t, std::string> fingerprints(const std::vector<EpisodeRow>& rows) {
    std::map<std::int64_t, std::string> out;
    for (const auto& r : rows) out[r.episode_id.value()] = orchestrator::verdict_fingerprint(r);
    return out;
  }

  // The merged recording holds each stored attempt once: one start per episode, of that attempt.
  void expect_one_start_per_episode(const std::string& out) {
    std::map<std::int64_t, std::vector<int>> starts;
    bus::for_each_recorded_event(fx_.root() / out, [&](const lcm::LogEvent& ev) {
      if (ev.channel != bus::kEpisodeStart) return;
      mtg::episode_start_t m{};
      ASSERT_GE(m.decode(ev.data, 0, ev.datalen), 0);
      starts[m.header.episode_id].push_back(m.header.attempt);
    });
    const auto rows = results(out);
    EXPECT_EQ(starts.size(), rows.size());
    for (const auto& r : rows) {
      ASSERT_EQ(starts[r.episode_id.value()].size(), 1u) << "episode " << r.episode_id;
      EXPECT_EQ(starts[r.episode_id.value()][0], r.attempt) << "episode " << r.episode_id;
    }
  }

  testing::FixtureDataset fx_;
  testing::BuiltScene built_;
  std::string tasks_db_;
  std::string prefix_;
  int hosts_ = 0;
  std::map<int, std::unique_ptr<testing::ChildProcess>> workers_;
  std::string shared_url_ = kSharedUrl;  // the bus the workers and the coordinator share
};

}  // namespace testing_multihost
}  // namespace mtg
