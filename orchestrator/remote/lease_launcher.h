#pragma once
// The coordinator's side of a multi-host run (`mtg run --remote`): episode attempts go to the
// workers (`mtg worker`) on the shared bus as leases (lcmtypes/lease_t.lcm).
//   - It announces the run once a second (run_info_t); workers join it, start their services
//     and heartbeat their capacity. Leases go to the worker with the most free slots.
//   - A grant is repeated until the worker renews it; workers renew each lease every second. A
//     lease not renewed for lease_ttl_s (the worker died, or was cut off) is revoked and
//     reported as a failure, so the engine re-runs the episode elsewhere as the next attempt.
//   - A worker sends a finished attempt's result together with its recording in chunks; only
//     when every chunk is there and the checksum holds is the recording written to the run
//     folder and the result handed to the engine, which stores it once. Then the lease is
//     released; until then the worker resends.
//   - Every grant is written to leases.sqlite first: a restarted coordinator adopts the leases
//     still out and numbers new attempts above the old ones.
// The rate governor for model agents runs here, on the shared bus, so its limits hold for every
// host together.

#include <chrono>
#include <deque>
#include <optional>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "bus/bus.h"
#include "bus/header.h"
#include "mtg/heartbeat_t.hpp"
#include "mtg/lease_t.hpp"
#include "mtg/record_chunk_t.hpp"
#include "mtg/recording_ref_t.hpp"
#include "orchestrator/remote/episode_log.h"
#include "orchestrator/remote/lease_book.h"
#include "orchestrator/remote/remote_options.h"
#include "orchestrator/run/launcher.h"
#include "orchestrator/run/local_runtime.h"
#include "orchestrator/run/supervisor.h"

namespace mtg::orchestrator::remote {

class LeaseLauncher final : public Launcher {
 public:
  /// `run` describes the run to workers (its bus_url is the shared bus); `counts` is read for
  /// the announcements.
  LeaseLauncher(RuntimeConfig run, std::filesystem::path run_dir, const RunCounts& counts, RemoteOptions options);

  std::vector<AdoptedAttempt> open() override;
  int free_slots() const override;
  int next_attempt(bus::EpisodeId episode_id) const override;
  void launch(const EpisodeLaunch& launch) override;
  void drop(bus::EpisodeId episode_id, int attempt) override;
  void poll(int timeout_ms, LaunchSink& sink) override;
  void close() override;
  int restarts() const override { return supervisor_.restarts(); }

 private:
  using Clock = std::chrono::steady_clock;
  struct Worker {
    std::string host;
    std::string session;  // its process's session: the lease messages to it go on its channel
    int held = 0;         // leases it holds (kept with leases_, so placement is not a scan)
    int capacity = 0;
    std::string status;
    Clock::time_point last_seen;
    // Heard within the lease TTL as of the last poll. Decided there, not at each question, so
    // free_slots() and the launch() that follows it agree on who is there.
    bool live = false;
  };
  struct Lease {
    int attempt = 0;
    std::string worker;
    EpisodeLaunch launch{};  // empty for an adopted lease (its grant was sent before)
    bool acknowledged = false;
    Clock::time_point last_renewal, last_grant;
  };
  using AttemptKey = std::pair<bus::EpisodeId, int>;
  std::set<std::string> worker_errors_;  // said once each
  std::int64_t announcements_ = 0;
  struct Arrival {
    std::optional<mtg::episode_result_t> result;
    ChunkAssembly chunks;
    std::optional<mtg::recording_ref_t> ref;  // the recording stayed on the worker or went to the shared folder
    int ref_misses = 0;                       // a shared file not (yet) seen here, as often
    std::string worker;
  };

  void subscribe();
  /// `echo`: the status challenge this announcement answers (session_rules.h, kStatusProbe).
  void announce(const std::string& state, const std::string& echo = "");
  /// The worker sessions heard within the lease TTL, oldest dropped beyond kHeardKept.
  std::vector<std::string> heard_sessions();
  /// Clears `live` of the workers not heard within the lease ttl (a heartbeat sets it again).
  void mark_silent_workers();
  int live_workers() const;
  int held_by(const std::string& worker) const;
  void send_lease(const std::string& action, bus::EpisodeId episode_id, int attempt, const std::string& worker,
                  const EpisodeLaunch* launch = nullptr);
  void on_renew(bus::EpisodeId id, int attempt, const std::string& worker);
  /// A lease of `l.worker` now out / no longer out (the worker's count follows).
  void hold(bus::EpisodeId id, Lease lease);
  void release_hold(std::map<bus::EpisodeId, Lease>::iterator it);
  /// The reference to store for an arrival (the shared file checked), or why it cannot be stored yet.
  std::optional<bus::RecordingRef> reference_of(const AttemptKey& key, const Arrival& a, std::string& why);
  void arrived(const AttemptKey& key);
  void remember_delivered(const AttemptKey& key);
  void expire_leases(LaunchSink& sink);
  /// Flushes the lease book, then sends the grants launch() wrote and the releases and
  /// revocations of the leases closed: each is on disk before it is out.
  void flush_book();
  void end_lease(const std::string& action, bus::EpisodeId id, int attempt, const std::string& worker);
  std::string lease_id(bus::EpisodeId episode_id, int attempt) const;
  /// Whether `sender` holds the lease of `key` (or the attempt was delivered before); warns once when not.
  bool from_holder(const AttemptKey& key, const std::string& sender, const char* what);

  RuntimeConfig run_;
  std::filesystem::path dir_;
  const RunCounts& counts_;
  RemoteOptions options_;
  bus::Bus bus_;
  std::shared_ptr<const bus::TruthSeal> truth_seal_;  // grants carry the answers sealed
  bus::HeaderStamper stamp_;
  Supervisor supervisor_;
  LeaseBook book_;
  std::map<bus::EpisodeId, int> last_attempt_;
  std::map<std::string, Worker> workers_;       // by sender id
  std::map<bus::EpisodeId, Lease> leases_;        // by episode id
  std::map<AttemptKey, Arrival> arrivals_;
  std::vector<AttemptKey> unsent_grants_;  // launched, waiting for the book's next flush
  struct LeaseEnd {
    std::string action;  // release, revoke
    bus::EpisodeId episode;
    int attempt = 0;
    std::string worker;
  };
  std::vector<LeaseEnd> unsent_ends_;  // closed in the book, waiting for its next flush
  // Answered with "release" when resent; the last kDeliveredKept only (a worker resends within
  // seconds, while thousands of episodes finish in between only on a very long run).
  static constexpr std::size_t kDeliveredKept = 16384;
  std::set<AttemptKey> delivered_;
  std::deque<AttemptKey> delivered_order_;
  std::deque<Clock::time_point> finish_times_;  // for the announced rate
  // This coordinator process's session (run_info_t.session). A worker counts, and a renewal
  // holds, only when it names this session: a heartbeat or renewal of an earlier invocation of
  // the same run, replayed, names another.
  std::string session_;
  // Worker sessions heard lately (named in each announcement, so a worker joins only a live
  // coordinator); at most kHeardKept, the least recently heard dropped first.
  static constexpr std::size_t kHeardKept = 256;
  std::map<std::string, Clock::time_point> heard_;
  bool fingerprints_due_ = false;  // a new worker was heard: the next announcement carries them
  LaunchSink* sink_ = nullptr;                  // during poll()
  Clock::time_point next_announce_;
  bool governor_ = false;
};

}  // namespace mtg::orchestrator::remote
