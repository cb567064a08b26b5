// Clusters without multicast (docs/multihost.md): simulated hosts that share no multicast route
// and meet over LCM's TCP hub (`mtg hub`), and workers launched by a real single-node Slurm
// cluster (scripts/slurm-local) through `mtg run --slurm`. Both give the results of one machine.

#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>

#include "bus/recording_ref.h"
#include "tests/bus/multihost_fixture.h"

namespace mtg {
namespace {

using testing_multihost::MultiHostTest;
using testing_multihost::read_text;
using testing_multihost::script;
namespace fs = std::filesystem;

constexpr const char* kSharedRoutes = "239.255.77.0/24";  // what scripts/netns-hosts routes between hosts

bool on_path(const std::string& program) {
  return std::system(("command -v " + program + " >/dev/null 2>&1 || test -x /usr/sbin/" + program).c_str()) == 0;
}

TEST_F(MultiHostTest, OverTheTcpHubHostsWithoutMulticastBetweenThemGiveTheResultsOfOneHost) {
  ASSERT_EQ(mtg(run_args("one", 3, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));

  make_hosts(2);
  // No multicast between the hosts: the shared groups now stay on each host's lo, as on a
  // network that does not carry multicast.
  for (int i = 0; i < 2; ++i) {
    ASSERT_EQ(sh({"/bin/sh", "-c", "ip -n " + host(i) + " route del " + kSharedRoutes}), 0) << log_text();
  }
  ASSERT_EQ(sh({"/bin/sh", "-c", std::string("ip route del ") + kSharedRoutes}), 0) << log_text();
  const std::string route = (fx_.root() / "route.txt").string();
  {
    testing::ChildProcess get({script("netns-hosts"), "exec", host(0), "ip", "route", "get", "239.255.77.1"}, route);
    ASSERT_EQ(get.wait(10000), 0);
  }
  ASSERT_NE(read_text(route).find(" dev lo "), std::string::npos) << read_text(route);

  testing::ChildProcess hub({testing::bin("mtg"), "hub", "--port", "7790"}, (fx_.root() / "hub.log").string());
  shared_url_ = "tcpq://10.77.0.254:7790";  // the bridge: where the hosts reach this namespace
  for (int i = 0; i < 2; ++i) start_worker(i);
  ASSERT_EQ(mtg(run_args("hub", 3, 4, 2)), 0) << log_text();
  const auto rows = results("hub");
  EXPECT_EQ(fingerprints(rows), single);
  std::set<std::string> used;
  for (const auto& r : rows) used.insert(r.worker);
  EXPECT_EQ(used.size(), 2u) << "the run spread over both hosts";
  expect_one_start_per_episode("hub");

  // The workers stay on the hub after the run: mtg status sees them there.
  const fs::path status_file = fx_.root() / "status.json";
  // stdout alone: liblcm says "LCM tcpq: connecting..." on stderr.
  ASSERT_EQ(sh({"/bin/sh", "-c", testing::bin("mtg") + " status --bus " + shared_url_ + " --json > " + status_file.string()}), 0)
      << log_text();
  const auto status = nlohmann::json::parse(read_text(status_file));
  EXPECT_EQ(status["workers"].size(), 2u) << status.dump();
}

// A real Slurm cluster of one node (this machine, in the test's namespace), started and stopped
// by the test; `mtg run --slurm` submits the workers to it as a job array.
class SlurmTest : public MultiHostTest {
 protected:
  void SetUp() override {
    MultiHostTest::SetUp();
    if (IsSkipped()) return;
    for (const std::string p : {"sbatch", "scancel", "slurmctld", "slurmd", "munged", "java"}) {
      if (!on_path(p)) GTEST_SKIP() << p << " is missing: scripts/install-deps installs Slurm, munge and java";
    }
    slurm_dir_ = fx_.root() / "slurm-cluster";
    const std::string up_log = (fx_.root() / "slurm-up.log").string();
    testing::ChildProcess up({script("slurm-local"), "up", slurm_dir_.string()}, up_log);
    ASSERT_EQ(up.wait(60000), 0) << read_text(up_log);
    slurm_up_ = true;
    ::setenv("SLURM_CONF", (slurm_dir_ / "slurm.conf").c_str(), 1);
    ::unsetenv("MTG_BUS_KEY");  // a Slurm run without a key makes its own
  }

  void TearDown() override {
    if (slurm_up_) sh({script("slurm-local"), "down", slurm_dir_.string()});
    ::unsetenv("SLURM_CONF");
    MultiHostTest::TearDown();
  }

  std::vector<std::string> slurm_run_args(const std::string& out, int limit) {
    auto args = run_args(out, limit, 4, 0);
    for (const std::string a : {"--slurm=--time=10", "--slurm-workers", "2", "--worker-capacity", "2", "--lease-ttl",
                                "2", "--min-workers", "2"}) {
      args.push_back(a);
    }
    return args;
  }

  // The sender id a Slurm worker announced in its log ("worker:<host>:<pid> on tcpq://...").
  std::string worker_sender(const std::string& out, int task) {
    static const std::regex line(R"((worker:\S+) on tcpq://)");
    std::smatch m;
    const std::string text = read_text(fx_.root() / out / "slurm" / ("worker-" + std::to_string(task) + ".log"));
    return std::regex_search(text, m, line) ? m[1].str() : std::string();
  }

  fs::path slurm_dir_;
  bool slurm_up_ = false;
};

TEST_F(SlurmTest, AJobArrayOfWorkersGivesTheResultsOfOneMachineAndIsCancelledAtTheEnd) {
  ASSERT_EQ(mtg(run_args("one", 4, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));

  ASSERT_EQ(mtg(slurm_run_args("array", 4)), 0) << log_text();
  const auto rows = results("array");
  EXPECT_EQ(rows.size(), planned("array"));
  EXPECT_EQ(fingerprints(rows), single);
  std::set<std::string> used;
  for (const auto& r : rows) used.insert(r.worker);
  EXPECT_EQ(used.size(), 2u) << "both array tasks ran episodes";
  expect_one_start_per_episode("array");
  EXPECT_EQ(fs::status(fx_.root() / "array" / "bus.key").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);

  // Nothing of the array is left once the run has returned.
  const std::string job = read_text(fx_.root() / "array" / "slurm" / "job_id");
  ASSERT_FALSE(job.empty());
  const std::string queue = (fx_.root() / "squeue.txt").string();
  EXPECT_TRUE(wait_for([&] {
    testing::ChildProcess q({"/bin/sh", "-c", "squeue -h -o '%i %T' -j " + job.substr(0, job.find('\n'))}, queue);
    q.wait(10000);
    return read_text(queue).find_first_not_of(" \n") == std::string::npos;
  }, 30000)) << read_text(queue);

  // The cluster's shared file system holds the recordings: the array tasks write them there, only
  // references reach the coordinator, and the run reads as the merged one.
  const fs::path cluster_fs = fx_.root() / "cluster-fs";
  auto shared_args = slurm_run_args("array-shared", 4);
  shared_args.push_back("--recordings=shared:" + cluster_fs.string());
  ASSERT_EQ(mtg(shared_args), 0) << log_text();
  EXPECT_EQ(fingerprints(results("array-shared")), single);
  EXPECT_FALSE(fs::exists(fx_.root() / "array-shared" / "episodes"));
  const auto refs = bus::read_recording_refs(fx_.root() / "array-shared" / "results.sqlite");
  EXPECT_EQ(refs.size(), rows.size());
  for (const auto& r : refs) EXPECT_EQ(r.location.rfind(cluster_fs.string(), 0), 0u) << r.location;
  expect_one_start_per_episode("array-shared");
  const std::string rejudged = (fx_.root() / "rejudge.txt").string();
  testing::ChildProcess rejudge({testing::bin("mtg"), "rejudge", (fx_.root() / "array-shared").string()}, rejudged);
  EXPECT_EQ(rejudge.wait(60000), 0) << read_text(rejudged);
  EXPECT_NE(read_text(rejudged).find(std::to_string(rows.size()) + " identical, 0 differ"), std::string::npos)
      << read_text(rejudged);
}

TEST_F(SlurmTest, AnArrayTaskKilledMidRunLosesNoEpisodeAndRunsNoneTwice) {
  ASSERT_EQ(mtg(run_args("one", 8, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));

  // Array task 1 never delivers: its leases stay held until its node is lost.
  ::setenv("MTG_FAULTS", "hold_results_in_array_task:1", 1);
  testing::ChildProcess run(slurm_run_args("killed", 8), log());
  ::unsetenv("MTG_FAULTS");
  std::string victim;
  auto victim_holds_a_lease = [&] {
    if (victim.empty()) victim = worker_sender("killed", 1);
    const auto held = open_leases("killed");
    return !victim.empty() && held.count(victim) > 0 && held.at(victim) > 0;
  };
  ASSERT_TRUE(wait_for(victim_holds_a_lease, 120000)) << log_text();
  const std::string job = read_text(fx_.root() / "killed" / "slurm" / "job_id");
  ASSERT_EQ(sh({"/bin/sh", "-c", "scancel --full --signal=KILL " + job.substr(0, job.find('\n')) + "_1"}), 0)
      << log_text();
  ASSERT_EQ(run.wait(180000), 0) << log_text();

  const auto rows = results("killed");
  EXPECT_EQ(rows.size(), planned("killed"));
  EXPECT_EQ(fingerprints(rows), single);
  expect_one_start_per_episode("killed");
  int retried = 0;
  for (const auto& r : rows) retried += r.attempt > 0 ? 1 : 0;
  EXPECT_GT(retried, 0) << "the lost task's leases were re-issued";
  EXPECT_NE(log_text().find("not renewed"), std::string::npos) << log_text();
}

}  // namespace
}  // namespace mtg
