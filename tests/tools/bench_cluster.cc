// mtg_bench_cluster (scripts/bench cluster): multi-host figures on simulated hosts (network
// namespaces joined by a bridge, scripts/netns-hosts; run it inside `unshare -n -m` as root).
//   1. throughput of the same oracle run on this machine alone and on 1, 2 and 3 hosts (the
//      same cores, so the ratio to the one-machine run is the per-core efficiency), with the
//      coordinator's and workers' own CPU time per episode and the shared bus's bytes per episode;
//   2. a host killed mid-run: time until its leases expire (detection) and until its episodes
//      are stored from other hosts (recovery);
//   3. bytes on the shared bus per episode with and without images, by channel;
//   4. the same over LCM's TCP hub (`mtg hub`) with no multicast between the hosts: episodes/s,
//      bytes, and the hub's CPU per message; then 4 to 16 hosts on one hub, to see how close
//      the hub comes to being the bottleneck.

#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/store/sqlite.h"
#include "orchestrator/remote/lease_book.h"
#include "orchestrator/run/process_memory.h"
#include "orchestrator/run/results_db.h"
#include "tests/support/process.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using mtg::testing::ChildProcess;

constexpr const char* kShared = "udpm://239.255.77.1:7701?ttl=1";
constexpr const char* kHubPort = "7790";
constexpr const char* kHubUrl = "tcpq://10.77.0.254:7790";  // the bridge, where every host reaches the caller
constexpr const char* kSharedRoutes = "239.255.77.0/24";     // scripts/netns-hosts routes these between hosts

enum class SharedBus { kMulticast, kHub };

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// User + system CPU seconds of one live process (its children not included).
double cpu_seconds(pid_t pid) { return mtg::orchestrator::process_cpu_seconds(pid); }

class Bench {
 public:
  Bench(std::string root, fs::path work, std::string tasks) : root_(std::move(root)), work_(std::move(work)), tasks_(std::move(tasks)) {}
  ~Bench() { down(); }

  std::string script() const { return root_ + "/scripts/netns-hosts"; }
  std::string mtg() const { return root_ + "/build/bin/mtg"; }

  void up(int n, SharedBus bus = SharedBus::kMulticast, int capacity = 4) {
    down();
    ChildProcess clean({script(), "down", "bh", "16"}, (work_ / "netns.log").string());  // left by an aborted bench
    clean.wait(60000);
    ChildProcess p({script(), "up", "bh", std::to_string(n)}, (work_ / "netns.log").string());
    if (p.wait(60000) != 0) throw std::runtime_error("netns-hosts up failed (root? see " + (work_ / "netns.log").string() + ")");
    hosts_ = n;
    url_ = kShared;
    if (bus == SharedBus::kHub) {
      // No multicast between the hosts, as on a cloud or HPC network: the groups stay on each lo.
      std::string cut = std::string("ip route del ") + kSharedRoutes;
      for (int i = 0; i < n; ++i) cut += " && ip -n bh" + std::to_string(i) + " route del " + kSharedRoutes;
      ChildProcess c({"/bin/sh", "-c", cut}, (work_ / "netns.log").string());
      if (c.wait(60000) != 0) throw std::runtime_error("cannot remove the multicast routes: " + cut);
      hub_ = std::make_unique<ChildProcess>(std::vector<std::string>{mtg(), "hub", "--port", kHubPort},
                                            (work_ / "hub.log").string());
      url_ = kHubUrl;
    }
    for (int i = 0; i < n; ++i) {
      workers_.push_back(std::make_unique<ChildProcess>(
          std::vector<std::string>{script(), "exec", "bh" + std::to_string(i), mtg(), "--log-level", "warn", "worker",
                                   "--bus", url_, "--name", "host" + std::to_string(i), "--capacity",
                                   std::to_string(capacity), "--dir", (work_ / ("worker" + std::to_string(i))).string()},
          (work_ / ("worker" + std::to_string(i) + ".log")).string()));
    }
  }

  void down() {
    workers_.clear();
    hub_.reset();
    if (hosts_ > 0) {
      ChildProcess p({script(), "down", "bh", std::to_string(hosts_)}, (work_ / "netns.log").string());
      p.wait(60000);
    }
    hosts_ = 0;
  }

  std::vector<std::string> run_args(const std::string& out, int limit, bool remote, bool render, int parallel = 4,
                                    const std::vector<std::string>& extra = {}) const {
    std::vector<std::string> a = {mtg(), "--log-level", "warn", "run", "--tasks", tasks_, "--agent", "oracle",
                                  "--levels", "1,2,3", "--limit", std::to_string(limit), "--parallel",
                                  std::to_string(parallel), "--out", (work_ / out).string(), "--no-progress"};
    if (remote) {
      a.insert(a.end(), {"--remote", "--bus", url_, "--min-workers", std::to_string(hosts_)});
    }
    if (render) {
      for (const char* s : {"--render", "--image-size", "640x480"}) a.emplace_back(s);
    }
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }

  struct RunFigures {
    double seconds = 0, episodes = 0, coordinator_cpu = 0, worker_cpu = 0;
    double steady_seconds = 0;  // from the first stored result on (scenes loaded, processes up)
    double hub_cpu = 0;         // the hub's user + system seconds during the run (0 without a hub)
    double coordinator_episode_cpu = -1;  // per episode, first to last result (without merge and report)
    std::map<std::string, std::pair<std::int64_t, std::int64_t>> shared_bytes;  // channel -> (messages, bytes)
  };

  // One run; `record` puts a recorder on the shared bus to count its traffic (over a hub it is
  // one more client the hub relays everything to).
  RunFigures run(const std::string& out, int limit, bool remote, bool render, int parallel = 4, bool record = true,
                 const std::vector<std::string>& extra = {}) {
    fs::remove_all(work_ / out);
    const fs::path shared_log = work_ / (out + "-shared.lcmlog");
    fs::remove(shared_log);
    std::unique_ptr<ChildProcess> recorder;
    if (remote && record) {
      recorder = std::make_unique<ChildProcess>(
          std::vector<std::string>{root_ + "/build/bin/mtg_recorder", "--url", url_, shared_log.string()},
          (work_ / "shared-recorder.log").string());
      while (!fs::exists(shared_log)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::vector<double> worker_cpu_before;
    for (const auto& w : workers_) worker_cpu_before.push_back(cpu_seconds(w->pid()));
    const double hub_before = hub_ ? cpu_seconds(hub_->pid()) : 0.0;
    const auto start = Clock::now();
    ChildProcess p(run_args(out, limit, remote, render, parallel, extra), (work_ / (out + ".log")).string());
    // The coordinator's CPU from its first stored result on: planning and loading the task set
    // happen once per run, whatever the number of episodes.
    double coordinator_cpu = 0.0, cpu_at_first = -1.0, cpu_at_last = -1.0;
    Clock::time_point first_result = start;
    std::size_t stored_at_first = 0;
    std::int64_t planned = -1;
    while (p.running()) {
      coordinator_cpu = std::max(coordinator_cpu, cpu_seconds(p.pid()));
      if (cpu_at_first >= 0 && cpu_at_last < 0) {
        // Up to the last result: what follows (merging, the report) is once per run.
        try {
          if (planned < 0) {
            std::ifstream in(work_ / out / "plan.json");
            const std::string text((std::istreambuf_iterator<char>(in)), {});
            planned = static_cast<std::int64_t>(nlohmann::json::parse(text)["episodes"].size());
          }
          mtg::store::Database db(work_ / out / "results.sqlite", mtg::store::Database::Mode::kReadOnly);
          mtg::store::Statement q(db, "SELECT COUNT(*) FROM episodes");
          if (q.step() && q.column_int(0) >= planned) cpu_at_last = coordinator_cpu;
        } catch (const std::exception&) {
        }
      }
      if (cpu_at_first < 0) {
        try {
          stored_at_first = mtg::orchestrator::read_results(work_ / out / "results.sqlite").size();
          if (stored_at_first > 0) {
            cpu_at_first = coordinator_cpu;
            first_result = Clock::now();
          }
        } catch (const std::exception&) {
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (p.wait(1000) != 0) throw std::runtime_error("mtg run failed: see " + (work_ / (out + ".log")).string());
    RunFigures f;
    f.seconds = seconds_since(start);
    f.steady_seconds = seconds_since(first_result);
    f.episodes = static_cast<double>(mtg::orchestrator::read_results(work_ / out / "results.sqlite").size());
    f.coordinator_cpu = cpu_at_first < 0 ? coordinator_cpu
                                         : (coordinator_cpu - cpu_at_first) * f.episodes /
                                               std::max(1.0, f.episodes - static_cast<double>(stored_at_first));
    if (cpu_at_first >= 0 && cpu_at_last >= 0) {
      f.coordinator_episode_cpu = (cpu_at_last - cpu_at_first) / std::max(1.0, f.episodes - static_cast<double>(stored_at_first));
    }
    for (std::size_t i = 0; i < workers_.size(); ++i) f.worker_cpu += cpu_seconds(workers_[i]->pid()) - worker_cpu_before[i];
    if (hub_) f.hub_cpu = cpu_seconds(hub_->pid()) - hub_before;
    if (recorder) {
      recorder->kill(SIGINT);
      lcm::LogFile log(shared_log.string(), "r");
      for (const lcm::LogEvent* ev = log.readNextEvent(); ev != nullptr; ev = log.readNextEvent()) {
        auto& [n, bytes] = f.shared_bytes[ev->channel];
        ++n;
        bytes += ev->datalen;
      }
    }
    return f;
  }

  // The coordinator's CPU per host and second with `hosts` workers joined and no episode: it waits
  // for one worker more than there are, for `seconds`, and gives up (heartbeats, announcements).
  double idle_cpu_per_host_second(int hosts, double seconds) {
    const std::string out = "idle-" + std::to_string(hosts);
    fs::remove_all(work_ / out);
    std::vector<std::string> args = run_args(out, 1, false, false);
    args.insert(args.end(), {"--remote", "--bus", url_, "--min-workers", std::to_string(hosts + 1), "--worker-wait",
                             std::to_string(static_cast<int>(seconds))});
    ChildProcess p(args, (work_ / (out + ".log")).string());
    // From the moment every worker is heard (its announcements name them) to the give-up.
    std::this_thread::sleep_for(std::chrono::seconds(3));
    const double before = cpu_seconds(p.pid());
    const auto t0 = Clock::now();
    double last = before;
    while (p.running()) {
      last = std::max(last, cpu_seconds(p.pid()));
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    p.wait(1000);  // exit 1: not enough workers, as asked
    return (last - before) / std::max(1e-9, seconds_since(t0)) / hosts;
  }

  // Kills host `victim` while it holds leases; returns (detect s, recover s, episodes it lost).
  std::tuple<double, double, int> kill_host(int limit, int victim) {
    const std::string out = "kill";
    fs::remove_all(work_ / out);
    ChildProcess p(run_args(out, limit, true, false), (work_ / "kill.log").string());
    const pid_t worker_pid = workers_[static_cast<std::size_t>(victim)]->pid();
    const std::string suffix = ":" + std::to_string(worker_pid);
    auto victim_leases = [&](mtg::orchestrator::remote::LeaseState state) {
      std::set<std::int64_t> ids;
      try {
        mtg::store::Database db(work_ / out / "leases.sqlite", mtg::store::Database::Mode::kReadOnly);
        mtg::store::Statement q(db, "SELECT episode_id, worker FROM leases WHERE state = ?");
        q.bind(1, mtg::orchestrator::remote::to_string(state));
        while (q.step()) {
          const std::string w = q.column_text(1);
          if (w.size() > suffix.size() && w.compare(w.size() - suffix.size(), suffix.size(), suffix) == 0) {
            ids.insert(q.column_int(0));
          }
        }
      } catch (const std::exception&) {
      }
      return ids;
    };
    auto stored = [&] {
      std::set<std::int64_t> done;
      try {
        for (const auto& r : mtg::orchestrator::read_results(work_ / out / "results.sqlite")) done.insert(r.episode_id.value());
      } catch (const std::exception&) {
      }
      return done;
    };
    auto signal_host = [&](const std::string& signal) {
      ChildProcess k({"/bin/sh", "-c", "kill -" + signal + " $(ip netns pids bh" + std::to_string(victim) + ")"}, "");
      k.wait(10000);
    };
    // Mid-run (a tenth of the episodes done), while the victim holds leases it cannot finish:
    // freeze it, let what it already sent arrive, and kill it if leases are still out on it.
    Clock::time_point stopped_at;
    for (;;) {
      while (p.running() && (stored().size() < static_cast<std::size_t>(3 * limit / 10) || victim_leases(mtg::orchestrator::remote::LeaseState::kGranted).empty())) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
      if (!p.running()) throw std::runtime_error("the run ended before a host could be killed");
      signal_host("STOP");
      stopped_at = Clock::now();
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      if (!victim_leases(mtg::orchestrator::remote::LeaseState::kGranted).empty()) break;
      signal_host("CONT");
    }
    const auto killed = stopped_at;  // the host has been silent since then
    signal_host("9");
    double detect = -1, recover = -1;
    std::set<std::int64_t> lost;
    for (bool last = false; !last;) {
      last = !p.running();
      if (detect < 0 && !(lost = victim_leases(mtg::orchestrator::remote::LeaseState::kExpired)).empty()) detect = seconds_since(killed);
      if (detect >= 0 && recover < 0) {
        const auto done = stored();
        bool all = true;
        for (const auto id : lost) all = all && done.count(id) != 0;
        if (all) recover = seconds_since(killed);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (p.wait(60000) != 0) throw std::runtime_error("mtg run failed after the kill: see " + (work_ / "kill.log").string());
    return {detect, recover, static_cast<int>(lost.size())};
  }

 private:
  std::string root_;
  fs::path work_;
  std::string tasks_;
  int hosts_ = 0;
  std::string url_ = kShared;  // the shared bus of the hosts now up
  std::unique_ptr<ChildProcess> hub_;
  std::vector<std::unique_ptr<ChildProcess>> workers_;
};

// Bytes on the shared bus in one run, all channels.
std::int64_t bytes(const Bench::RunFigures& f) {
  std::int64_t n = 0;
  for (const auto& [ch, nb] : f.shared_bytes) n += nb.second;
  return n;
}

void print_bytes(const char* what, const Bench::RunFigures& f) {
  std::printf("  %s: %.0f bytes per episode on the shared bus\n", what, static_cast<double>(bytes(f)) / f.episodes);
  for (const auto& [ch, nb] : f.shared_bytes) {
    std::printf("    %-18s %8.1f messages  %10.0f bytes per episode\n", ch.c_str(),
                static_cast<double>(nb.first) / f.episodes, static_cast<double>(nb.second) / f.episodes);
  }
}

std::int64_t messages(const Bench::RunFigures& f) {
  std::int64_t n = 0;
  for (const auto& [ch, nb] : f.shared_bytes) n += nb.first;
  return n;
}

// What the hub cost in one run: per episode, per message published on it (`per_episode`
// messages, counted by a recorder in this run or a like one), and its share of a core.
void print_hub(const Bench::RunFigures& f, double per_episode) {
  std::printf("      hub: %.2f ms CPU per episode, %.1f us per message published (%.1f messages/episode), "
              "%.0f %% of one core; at that cost one hub core carries %.0f episodes/s\n",
              1000.0 * f.hub_cpu / f.episodes, 1e6 * f.hub_cpu / (per_episode * f.episodes), per_episode,
              100.0 * f.hub_cpu / f.seconds, f.hub_cpu > 0 ? f.episodes / f.hub_cpu : 0.0);
}

double messages_per_episode(const Bench::RunFigures& f) { return static_cast<double>(messages(f)) / f.episodes; }

// The coordinator as hosts are added (2, 4, 8; capacity 2 each, as many in flight as slots): its
// CPU per episode after its first result, and the shared bus's messages and bytes per episode by
// channel, text only and with 640x480 images (recordings sent to it, or kept in a shared folder).
// What grows with the hosts and what with the episodes is what docs/multihost.md extrapolates.
int scale_section(Bench& bench, int limit, const std::vector<std::string>& modes, const fs::path& work, bool images,
                  const std::vector<int>& host_counts) {
  std::printf("the coordinator at 2, 4 and 8 hosts (capacity 2 each; oracle on apt_0, Levels 1-3):\n");
  for (const bool render : {false, true}) {
    if (render && !images) continue;
    for (const std::string& mode : modes) {
      for (const int hosts : host_counts) {
        bench.up(hosts, SharedBus::kMulticast, 2);
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        std::vector<std::string> extra;
        if (mode != "coordinator") {
          const fs::path folder = work / ("recordings-" + std::to_string(hosts));
          fs::remove_all(folder);
          extra = {"--recordings", "shared:" + folder.string()};
        }
        const std::string name = std::string(render ? "images" : "text") + "-" + mode + "-" + std::to_string(hosts);
        const int per_level = render ? std::max(2, 2 * hosts / 3) : limit;
        const auto f = bench.run(name, per_level, true, render, 2 * hosts, true, extra);
        std::printf("  %-5s %-11s %d hosts: %4.0f episodes in %6.2f s; coordinator %.2f ms CPU per episode (first to "
                    "last result), workers %.2f ms; shared bus %.1f messages, %.0f bytes per episode\n",
                    render ? "image" : "text", mode.c_str(), hosts, f.episodes, f.seconds,
                    1000.0 * f.coordinator_episode_cpu, 1000.0 * f.worker_cpu / f.episodes,
                    messages_per_episode(f), static_cast<double>(bytes(f)) / f.episodes);
        // Each worker's lease channel (MTG_LEASE_<session>) counted as one.
        std::map<std::string, std::pair<std::int64_t, std::int64_t>> by_kind;
        for (const auto& [ch, nb] : f.shared_bytes) {
          const bool own = ch.rfind("MTG_LEASE_", 0) == 0 && ch != "MTG_LEASE_RENEW";
          auto& k = by_kind[own ? "MTG_LEASE_<worker>" : ch];
          k.first += nb.first;
          k.second += nb.second;
        }
        for (const auto& [ch, nb] : by_kind) {
          std::printf("        %-20s %8.2f messages %11.0f bytes per episode\n", ch.c_str(),
                      static_cast<double>(nb.first) / f.episodes, static_cast<double>(nb.second) / f.episodes);
        }
        std::fflush(stdout);
      }
    }
  }
  // Over the hub, which relays each message to every client subscribed to its channel: text runs,
  // the hub's CPU per episode (no recorder on the hub: it would be one more client).
  for (const std::string& mode : modes) {
    for (const int hosts : host_counts) {
      bench.up(hosts, SharedBus::kHub, 2);
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      std::vector<std::string> extra;
      if (mode != "coordinator") extra = {"--recordings", "shared:" + (work / ("hub-recordings-" + std::to_string(hosts))).string()};
      const auto f = bench.run("hub-" + mode + "-" + std::to_string(hosts), limit, true, false, 2 * hosts, false, extra);
      std::printf("  hub   %-11s %d hosts: %4.0f episodes in %6.2f s; hub %.3f ms CPU per episode, coordinator %.2f ms\n",
                  mode.c_str(), hosts, f.episodes, f.seconds, 1000.0 * f.hub_cpu / f.episodes,
                  1000.0 * f.coordinator_episode_cpu);
      std::fflush(stdout);
    }
  }
  for (const int hosts : host_counts) {
    bench.up(hosts, SharedBus::kMulticast, 2);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    std::printf("  idle coordinator, %d hosts joined: %.3f ms CPU per host and second\n", hosts,
                1000.0 * bench.idle_cpu_per_host_second(hosts, 10.0));
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"multi-host figures on simulated hosts (scripts/bench cluster)"};
  std::string root, tasks, work = "/tmp/mtg_bench_cluster";
  int limit = 300;
  std::string only;
  std::vector<std::string> modes = {"coordinator", "shared"};
  int scale_limit = 100;
  bool no_images = false;
  std::vector<int> host_counts = {2, 4, 8};
  app.add_option("--only", only, "one section: scale (the coordinator at 2, 4 and 8 hosts), or all (default)");
  app.add_option("--modes", modes, "with scale: recordings places to compare (coordinator, shared)");
  app.add_option("--scale-limit", scale_limit, "with scale: tasks per level of the text runs (default 100)");
  app.add_flag("--no-images", no_images, "with scale: text runs only");
  app.add_option("--hosts", host_counts, "with scale: host counts (default 2 4 8)");
  app.add_option("--root", root, "repository root")->required();
  app.add_option("--tasks", tasks, "task database (apt_0, Levels 1-3)")->required();
  app.add_option("--work", work, "scratch folder");
  app.add_option("--limit", limit, "tasks per level (default 300)");
  CLI11_PARSE(app, argc, argv);
  try {
    fs::remove_all(work);
    fs::create_directories(work);
    // The shared bus is authenticated: every simulated host reads the same key file.
    const fs::path key = fs::path(work) / "bus.key";
    std::ofstream(key) << "bench-secret-of-the-cluster-figures\n";
    ::setenv("MTG_BUS_KEY", key.c_str(), 1);
    Bench bench(root, work, tasks);
    if (only == "scale") return scale_section(bench, scale_limit, modes, work, !no_images, host_counts);
    std::printf("oracle on apt_0, Levels 1-3, %d tasks each, 4 episodes in flight; every host is a network\n"
                "namespace on this machine's %ld cores\n", limit, sysconf(_SC_NPROCESSORS_ONLN));
    const auto local = bench.run("local", limit, false, false);
    const double base = local.episodes / local.seconds;
    const double base_steady = local.episodes / local.steady_seconds;
    std::printf("  this machine alone (mtg run):  %5.0f episodes in %5.2f s = %6.1f episodes/s (%.1f after the first "
                "result)\n", local.episodes, local.seconds, base, base_steady);
    Bench::RunFigures two;
    for (int hosts = 1; hosts <= 3; ++hosts) {
      bench.up(hosts);
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      const auto f = bench.run("hosts" + std::to_string(hosts), limit, true, false);
      const std::int64_t shared = bytes(f);
      const double rate = f.episodes / f.seconds;
      const double steady = f.episodes / f.steady_seconds;
      std::printf("  %d host%s (mtg run --remote):     %5.0f episodes in %5.2f s = %6.1f episodes/s (%.1f after the "
                  "first result), per-core efficiency %.2f (%.2f); CPU per episode: coordinator %.2f ms (after its start), workers %.2f ms "
                  "(their own process); shared bus %.0f B/episode\n",
                  hosts, hosts == 1 ? " " : "s", f.episodes, f.seconds, rate, steady, rate / base, steady / base_steady,
                  1000.0 * f.coordinator_cpu / f.episodes, 1000.0 * f.worker_cpu / f.episodes,
                  static_cast<double>(shared) / f.episodes);
      if (hosts == 2) two = f;
    }
    bench.up(3);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    const auto [detect, recover, lost] = bench.kill_host(limit, 1);
    std::printf("  host killed mid-run (3 hosts, lease ttl 5 s): %d leases lost, expired after %.2f s, their "
                "episodes stored from other hosts %.2f s after the kill\n", lost, detect, recover);
    bench.up(2);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    print_bytes("without images (2 hosts)", two);
    const auto images = bench.run("images", 4, true, true);
    print_bytes("with 640x480 PNG images (2 hosts)", images);

    std::printf("over LCM's TCP hub (mtg hub in the coordinator's namespace), no multicast route between the hosts;\n"
                "a recorder on the hub counts the bytes (the hub relays everything to it as well):\n");
    Bench::RunFigures hub_two;
    for (int hosts = 1; hosts <= 3; ++hosts) {
      bench.up(hosts, SharedBus::kHub);
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      const auto f = bench.run("hub" + std::to_string(hosts), limit, true, false);
      const std::int64_t shared = bytes(f);
      std::printf("  %d host%s (--bus tcpq://):  %5.0f episodes in %5.2f s = %6.1f episodes/s (%.1f after the first "
                  "result), per-core efficiency %.2f; shared bus %.0f B/episode\n",
                  hosts, hosts == 1 ? " " : "s", f.episodes, f.seconds, f.episodes / f.seconds,
                  f.episodes / f.steady_seconds, f.episodes / f.seconds / base, static_cast<double>(shared) / f.episodes);
      print_hub(f, messages_per_episode(f));
      if (hosts == 2) {
        print_bytes("without images, over the hub (2 hosts)", f);
        hub_two = f;
      }
    }
    std::printf("  the hub alone (2 hosts, no recorder on the hub):\n");
    const auto bare = bench.run("hub-bare", limit, true, false, 4, false);
    std::printf("    %5.0f episodes in %5.2f s = %6.1f episodes/s\n", bare.episodes, bare.seconds, bare.episodes / bare.seconds);
    print_hub(bare, messages_per_episode(hub_two));
    bench.up(2, SharedBus::kHub);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    const auto hub_images = bench.run("hub-images", 4, true, true);
    print_bytes("with 640x480 PNG images, over the hub (2 hosts)", hub_images);
    print_hub(hub_images, messages_per_episode(hub_images));
    const auto bare_images = bench.run("hub-images-bare", 4, true, true, 4, false);
    std::printf("    the same without the recorder:\n");
    print_hub(bare_images, messages_per_episode(hub_images));
    std::printf("  one hub, many hosts (capacity 1 each, as many episodes in flight as hosts):\n");
    for (const int hosts : {4, 8, 16}) {
      bench.up(hosts, SharedBus::kHub, 1);
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      const auto f = bench.run("hub-many" + std::to_string(hosts), limit, true, false, hosts, false);
      std::printf("    %2d hosts: %5.0f episodes in %5.2f s = %6.1f episodes/s\n", hosts, f.episodes, f.seconds,
                  f.episodes / f.seconds);
      print_hub(f, messages_per_episode(hub_two));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mtg_bench_cluster: %s\n", e.what());
    return 1;
  }
  return 0;
}
