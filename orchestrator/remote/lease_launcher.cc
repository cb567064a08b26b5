#include "orchestrator/remote/lease_launcher.h"

#include <signal.h>

#include <algorithm>
#include <thread>

#include "agents/vlm/model_spec.h"
#include "bus/channels.h"
#include "bus/error_events.h"
#include "bus/process/heartbeat.h"
#include "bus/process/identity.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "mtg/episode_result_t.hpp"
#include "mtg/error_event_t.hpp"
#include "mtg/lease_renewal_t.hpp"
#include "mtg/run_control_t.hpp"
#include "mtg/run_info_t.hpp"
#include "orchestrator/remote/merge_recordings.h"
#include "orchestrator/remote/run_announcement.h"
#include "orchestrator/remote/session_rules.h"

namespace mtg::orchestrator::remote {

namespace fs = std::filesystem;

namespace {

double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

LeaseLauncher::LeaseLauncher(RuntimeConfig run, fs::path run_dir, const RunCounts& counts, RemoteOptions options)
    : run_(std::move(run)), dir_(std::move(run_dir)), counts_(counts), options_(options), bus_(run_.bus_url),
      stamp_(run_.run_id, process::sender_id("coordinator")), supervisor_(dir_ / "logs"),
      book_(dir_ / "leases.sqlite"), session_(bus::draw_session_token()) {
  options_.bus_key = bus::shared_bus_key_file(options_.bus_key);  // the governor signs with it too
  bus_.authenticate(bus::shared_bus_authenticator(options_.bus_key));
  // Grants carry the answers sealed with the key every host derives; the run folder keeps the
  // derived key (not the secret) for the viewer and rejudge.
  fs::create_directories(dir_);
  truth_seal_ = std::make_shared<const bus::TruthSeal>(bus::TruthSeal::for_run_folder(
      dir_, bus::TruthSeal::derived(bus::Authenticator::read_secret(options_.bus_key), run_.run_id)));
  subscribe();
}

std::string LeaseLauncher::lease_id(bus::EpisodeId episode_id, int attempt) const {
  return run_.run_id + "/" + to_string(episode_id) + "/" + std::to_string(attempt);
}

void LeaseLauncher::subscribe() {
  bus_.subscribe<mtg::heartbeat_t>(bus::kHeartbeat, [this](const std::string&, const mtg::heartbeat_t& m) {
    if (m.role != "worker" || m.session.empty()) return;
    const auto now = Clock::now();
    // A worker heard for the first time joins from the next announcement that names it: make
    // that one come now rather than within the second, with the fingerprints it joins with.
    if (heard_.count(m.session) == 0) {
      next_announce_ = now;
      fingerprints_due_ = true;
    }
    heard_[m.session] = now;
    Worker& w = workers_[m.header.sender];
    w.host = m.host;
    w.session = m.session;
    // A worker of another run or another coordinator session (an earlier invocation of this
    // run, whose heartbeats an attacker may replay), or one still starting, takes no lease.
    const auto status = process::parse_heartbeat_status(m.status);
    const bool takes_work = status != process::HeartbeatStatus::kStarting && status != process::HeartbeatStatus::kDraining;
    const bool ours = m.header.run_id == run_.run_id && m.serving == session_;
    w.capacity = ours && takes_work ? m.capacity : 0;
    w.status = m.status;
    w.last_seen = now;
    w.live = true;
  });
  bus_.subscribe<mtg::lease_t>(bus::kLease, [this](const std::string&, const mtg::lease_t& m) {
    // A renewal names the session it renews for: one of an earlier invocation is not ours.
    if (m.header.run_id == run_.run_id && m.action == "renew" && m.session == session_) {
      on_renew(bus::episode_of(m.header), m.header.attempt, m.worker);
    }
  });
  bus_.subscribe<mtg::lease_renewal_t>(bus::kLeaseRenewal, [this](const std::string&, const mtg::lease_renewal_t& m) {
    if (m.header.run_id != run_.run_id || m.session != session_) return;
    const std::size_t n = std::min(m.episode_ids.size(), m.attempts.size());
    for (std::size_t i = 0; i < n; ++i) on_renew(bus::EpisodeId(m.episode_ids[i]), m.attempts[i], m.worker);
  });
  bus_.subscribe<mtg::recording_ref_t>(bus::kRecordRef, [this](const std::string&, const mtg::recording_ref_t& m) {
    if (m.header.run_id != run_.run_id) return;
    const AttemptKey key{bus::episode_of(m.header), m.header.attempt};
    // Only where the run keeps recordings elsewhere, for the attempt it names, kept as the run says.
    const auto kind = options_.recordings.kind;
    const bool as_planned = (kind == RecordingsPlace::Kind::kShared && m.shared) ||
                            (kind == RecordingsPlace::Kind::kWorker && !m.shared);
    if (!as_planned || m.lease_id != lease_id(key.first, key.second)) {
      const std::string why = "a recording reference from " + m.header.sender + " does not fit the run (" +
                              options_.recordings.to_string() + "); ignored";
      if (worker_errors_.insert(why).second) log::warn(why + " (" + m.lease_id + ")");
      return;
    }
    if (!from_holder(key, m.header.sender, "recording reference")) return;
    if (delivered_.count(key) == 0) {
      Arrival& a = arrivals_[key];
      a.worker = m.header.sender;
      a.ref = m;
    }
    arrived(key);
  });
  bus_.subscribe<mtg::episode_result_t>(bus::kEpisodeResult, [this](const std::string&, const mtg::episode_result_t& m) {
    if (m.header.run_id != run_.run_id) return;
    const AttemptKey key{bus::episode_of(m.header), m.header.attempt};
    if (delivered_.count(key) == 0) arrivals_[key].result = m;
    arrived(key);
  });
  bus_.subscribe<mtg::record_chunk_t>(bus::kRecord, [this](const std::string&, const mtg::record_chunk_t& m) {
    if (m.header.run_id != run_.run_id) return;
    const AttemptKey key{bus::episode_of(m.header), m.header.attempt};
    if (!from_holder(key, m.header.sender, "recording chunk")) return;
    if (delivered_.count(key) == 0) {
      Arrival& a = arrivals_[key];
      a.worker = m.header.sender;
      try {
        a.chunks.add(m);
      } catch (const Error& e) {
        // A resend of a rebuilt recording: start over with the new version.
        log::warn(std::string(e.what()) + "; collecting it again");
        a.chunks = ChunkAssembly();
        a.chunks.add(m);
      }
    }
    arrived(key);
  });
  bus_.subscribe<mtg::run_control_t>(bus::kControl, [this](const std::string&, const mtg::run_control_t& m) {
    if (const auto nonce = status_challenge(m.command, m.argument)) announce("running", *nonce);
  });
  bus_.subscribe<mtg::error_event_t>(bus::kError, [this](const std::string&, const mtg::error_event_t& m) {
    if (m.header.run_id != run_.run_id) return;
    if (const auto agent = bus::stopped_agent(m)) {
      if (sink_ != nullptr) sink_->on_agent_stopped(*agent, m.message);
    } else if (worker_errors_.insert(m.message).second) {
      log::warn(m.message);  // e.g. a worker whose dataset differs stays out of the run
    }
  });
}

std::vector<AdoptedAttempt> LeaseLauncher::open() {
  last_attempt_ = book_.last_attempts();
  std::vector<AdoptedAttempt> adopted;
  const auto now = Clock::now();
  for (const LeaseRecord& l : book_.open_leases()) {
    // Still out when the last coordinator stopped: its worker renews it if it is running it.
    Lease lease;
    lease.attempt = l.attempt;
    lease.worker = l.worker;
    lease.acknowledged = true;
    lease.last_renewal = lease.last_grant = now;
    hold(l.episode_id, lease);
    adopted.push_back({l.episode_id, l.attempt});
  }
  if (!adopted.empty()) log::info("adopting " + std::to_string(adopted.size()) + " leases still out");
  if (options_.recordings.kind == RecordingsPlace::Kind::kShared) {
    // A worker joins only where it reads this file with this session in it: the folder is then
    // the one the coordinator sees.
    const fs::path folder = options_.recordings.run_folder(run_.run_id);
    fs::create_directories(folder);
    write_file_atomically(folder / kSharedProbe, [&](std::ostream& out) { out << session_ << '\n'; });
    log::info("recordings stay in " + folder.string() + "; only references cross the bus");
  }
  const bool model_agents = std::any_of(run_.agents.begin(), run_.agents.end(), vlm::is_model_spec);
  if (model_agents) {
    supervisor_.start("governor", {(executable_dir() / "mtg_governor").string(), "--url", run_.bus_url, "--run",
                                   run_.run_id, "--bus-key", options_.bus_key});
    governor_ = true;
  }
  // Wait for the workers (announcing the run so they join).
  const auto deadline = now + std::chrono::duration<double>(options_.worker_wait_s);
  next_announce_ = now;
  log::info("waiting for " + std::to_string(options_.min_workers) + " worker(s) on " + run_.bus_url);
  while (live_workers() < options_.min_workers) {
    if (Clock::now() > deadline) {
      throw Error("only " + std::to_string(live_workers()) + " of " + std::to_string(options_.min_workers) +
                  " workers joined in " + std::to_string(static_cast<int>(options_.worker_wait_s)) + " s on " +
                  run_.bus_url + " (start `mtg worker --bus <url>` on each host; docs/multihost.md)");
    }
    if (Clock::now() >= next_announce_) {
      announce("running");
      next_announce_ += std::chrono::seconds(1);
    }
    bus_.handle_once(50);
    mark_silent_workers();
  }
  log::info(std::to_string(live_workers()) + " worker(s) joined");
  return adopted;
}

void LeaseLauncher::mark_silent_workers() {
  const auto now = Clock::now();
  for (auto& [id, w] : workers_) w.live = w.live && seconds_between(w.last_seen, now) < options_.lease_ttl_s;
}

int LeaseLauncher::live_workers() const {
  int n = 0;
  for (const auto& [id, w] : workers_) {
    if (w.capacity > 0 && w.live) ++n;
  }
  return n;
}

int LeaseLauncher::held_by(const std::string& worker) const {
  const auto it = workers_.find(worker);
  return it == workers_.end() ? 0 : it->second.held;
}

void LeaseLauncher::hold(bus::EpisodeId id, Lease lease) {
  const auto old = leases_.find(id);
  if (old != leases_.end()) release_hold(old);
  ++workers_[lease.worker].held;
  leases_[id] = std::move(lease);
}

void LeaseLauncher::release_hold(std::map<bus::EpisodeId, Lease>::iterator it) {
  const auto w = workers_.find(it->second.worker);
  if (w != workers_.end() && w->second.held > 0) --w->second.held;
  leases_.erase(it);
}

int LeaseLauncher::free_slots() const {
  int free = 0;
  for (const auto& [id, w] : workers_) {
    if (w.live) free += std::max(0, w.capacity - held_by(id));
  }
  return free;
}

int LeaseLauncher::next_attempt(bus::EpisodeId episode_id) const {
  const auto it = last_attempt_.find(episode_id);
  return it == last_attempt_.end() ? 0 : it->second + 1;
}

void LeaseLauncher::send_lease(const std::string& action, bus::EpisodeId episode_id, int attempt,
                               const std::string& worker, const EpisodeLaunch* launch) {
  mtg::lease_t m{};
  m.header = stamp_.next(episode_id, attempt, "lease");
  m.lease_id = lease_id(episode_id, attempt);
  m.worker = worker;
  m.action = action;
  m.session = session_;
  m.ttl_ms = static_cast<std::int32_t>(options_.lease_ttl_s * 1000.0);
  if (launch != nullptr) {
    m.task_id = launch->start.task.task_id;
    m.start = launch->start;
    m.truth = truth_seal_->seal(launch->truth);
  }
  // On the worker's own channel, so no other worker wakes for it. A worker not heard yet (an
  // adopted lease's, before its first heartbeat) is told when it is: its renewals are answered.
  const auto w = workers_.find(worker);
  if (w == workers_.end() || w->second.session.empty()) return;
  bus_.publish(bus::lease_channel(w->second.session), m);
}

void LeaseLauncher::launch(const EpisodeLaunch& launch) {
  const mtg::episode_start_t& start = launch.start;
  // The worker with the most free slots; ties go to the first by id.
  std::string best;
  int best_free = 0;
  for (const auto& [id, w] : workers_) {
    if (!w.live) continue;
    const int free = w.capacity - held_by(id);
    if (free > best_free) {
      best = id;
      best_free = free;
    }
  }
  if (best.empty()) throw Error("internal: launch() without a free worker slot");
  const bus::EpisodeId id = bus::episode_of(start.header);
  const int attempt = start.header.attempt;
  book_.grant({id, attempt, best});  // on disk before it is out: sent once the book is flushed (flush_book)
  unsent_grants_.push_back({id, attempt});
  last_attempt_[id] = std::max(last_attempt_[id], attempt);
  Lease lease;
  lease.attempt = attempt;
  lease.worker = best;
  lease.launch = launch;
  lease.last_renewal = lease.last_grant = Clock::now();
  hold(id, std::move(lease));
}

void LeaseLauncher::drop(bus::EpisodeId episode_id, int attempt) {
  const auto it = leases_.find(episode_id);
  if (it == leases_.end() || it->second.attempt != attempt) return;
  book_.close(episode_id, attempt, LeaseState::kRevoked);
  end_lease("revoke", episode_id, attempt, it->second.worker);
  release_hold(it);
}

void LeaseLauncher::on_renew(bus::EpisodeId id, int attempt, const std::string& worker) {
  const auto it = leases_.find(id);
  if (it != leases_.end() && it->second.attempt == attempt && it->second.worker == worker) {
    it->second.acknowledged = true;
    it->second.last_renewal = Clock::now();
    return;
  }
  // A lease this coordinator no longer counts on (expired, revoked, or finished and the release
  // was lost): the worker drops it. Its result, if one comes, is answered with a release.
  if (delivered_.count({id, attempt}) != 0) {
    send_lease("release", id, attempt, worker);
  } else {
    send_lease("revoke", id, attempt, worker);
  }
  if (it == leases_.end()) stamp_.forget_episode(id);
}

bool LeaseLauncher::from_holder(const AttemptKey& key, const std::string& sender, const char* what) {
  // A recording comes from the worker the attempt was leased to: another key holder's (or a
  // worker's for an attempt it does not hold) is not collected, whatever it names.
  const auto lease = leases_.find(key.first);
  if (lease != leases_.end() && lease->second.attempt == key.second && lease->second.worker == sender) return true;
  if (delivered_.count(key) != 0) return true;  // a resend after the release was lost: arrived() answers it
  const std::string why = std::string("a ") + what + " of " + lease_id(key.first, key.second) + " from " + sender +
                          ", which does not hold its lease; ignored";
  if (worker_errors_.insert(why).second) log::warn(why);
  return false;
}

void LeaseLauncher::arrived(const AttemptKey& key) {
  const auto [id, attempt] = key;
  if (delivered_.count(key) != 0) {
    // Resent after the release was lost: nothing to collect. The worker keeps renewing the
    // lease meanwhile, and on_renew() answers that with another release.
    const auto a = arrivals_.find(key);
    if (a != arrivals_.end()) arrivals_.erase(a);
    return;
  }
  Arrival& a = arrivals_[key];
  if (!a.result || (!a.ref && !a.chunks.complete()) || sink_ == nullptr) return;
  std::optional<bus::RecordingRef> ref;
  if (a.ref) {
    std::string why;
    ref = reference_of(key, a, why);
    if (!ref) {
      if (++a.ref_misses == 3) {
        // Seen three times (the worker resends every 3 s), never there: the folder is not shared.
        log::error(why + "; the attempt runs again");
        arrivals_.erase(key);
        const auto lease = leases_.find(id);
        if (lease != leases_.end() && lease->second.attempt == attempt) {
          const std::string worker = lease->second.worker;
          book_.close(id, attempt, LeaseState::kRevoked);
          release_hold(lease);
          end_lease("revoke", id, attempt, worker);
          sink_->on_failure(id, attempt, why);
        }
        return;
      }
      log::warn(why + "; waiting for the worker to send it again");
      a.result.reset();  // the next resend brings both, and is checked once
      a.ref.reset();
      return;
    }
  } else {
    std::vector<std::uint8_t> bytes;
    try {
      bytes = a.chunks.bytes();
      (void)decode_event_log(bytes, lease_id(id, attempt));
    } catch (const Error& e) {
      log::warn(std::string(e.what()) + "; waiting for the worker to resend it");
      a.chunks = ChunkAssembly();
      return;
    }
    // Whole or not at all: a killed coordinator leaves no half file.
    const fs::path file = store_episode_log(dir_, id, attempt, bytes);
    if (options_.recordings.kind != RecordingsPlace::Kind::kCoordinator) {
      // A worker that could not keep it sent it here: the run's references name this copy.
      ref = bus::relative_to(bus::reference_to(id, attempt, file.string(), "", true, bytes), dir_);
    }
  }
  const mtg::episode_result_t result = *a.result;
  const std::string worker = a.worker;
  arrivals_.erase(key);
  remember_delivered(key);
  finish_times_.push_back(Clock::now());
  const auto lease = leases_.find(id);
  std::string host = worker;
  const auto w = workers_.find(worker);
  if (w != workers_.end()) host = w->second.host;
  if (lease != leases_.end() && lease->second.attempt == attempt) {
    release_hold(lease);
    book_.close(id, attempt, LeaseState::kDone);
    sink_->on_result(result, host, ref ? &*ref : nullptr);
    last_attempt_.erase(id);  // stored: no attempt of it is numbered again
  }
  end_lease("release", id, attempt, worker);
}

std::optional<bus::RecordingRef> LeaseLauncher::reference_of(const AttemptKey& key, const Arrival& a, std::string& why) {
  bus::RecordingRef ref = bus::from_message(*a.ref);
  // A reference fits its run or is refused (issue 55: a key holder once had /etc/passwd kept as
  // a recording): this very attempt's, at the path the run's layout gives it, in the shared
  // folder's <run id>/ or a worker's <dir>/<run id>/episodes/, of a plausible size.
  const fs::path location(ref.location);
  const fs::path folder = location.parent_path();
  std::string misfit;
  if (ref.episode != key.first || ref.attempt != key.second) {
    misfit = "names another attempt";
  } else if (!location.is_absolute() || location.lexically_normal() != location) {
    misfit = "is not an absolute path without . or ..";
  } else if (ref.shared ? folder != options_.recordings.run_folder(run_.run_id).lexically_normal()
                        : folder.filename() != "episodes" || folder.parent_path().filename() != run_.run_id) {
    misfit = ref.shared ? "is not in this run's shared folder " + options_.recordings.run_folder(run_.run_id).string()
                        : "is not in a worker's <dir>/" + run_.run_id + "/episodes/";
  } else {
    misfit = bus::recording_misfit(location, ref);
  }
  if (!misfit.empty()) {
    why = "the recording reference of " + lease_id(key.first, key.second) + " (" + ref.location + ") " + misfit;
    return std::nullopt;
  }
  if (ref.shared) {
    // What a shared folder holds is checked here by size (its bytes are checked by whoever reads
    // it: reading every recording here is what the shared folder saves).
    std::error_code ec;
    const auto size = fs::file_size(ref.location, ec);
    if (ec || static_cast<std::int64_t>(size) != ref.bytes) {
      why = "the recording of " + lease_id(key.first, key.second) + " is not in the shared folder here (" +
            ref.location + (ec ? " is missing" : " has " + std::to_string(size) + " bytes, not " + std::to_string(ref.bytes)) +
            "); is " + options_.recordings.folder.string() + " the same folder on every host?";
      return std::nullopt;
    }
  }
  return bus::relative_to(std::move(ref), dir_);
}

void LeaseLauncher::expire_leases(LaunchSink& sink) {
  const auto now = Clock::now();
  std::vector<bus::EpisodeId> expired;
  for (auto& [id, l] : leases_) {
    if (seconds_between(l.last_renewal, now) > options_.lease_ttl_s) {
      expired.push_back(id);
    } else if (!l.acknowledged && seconds_between(l.last_grant, now) >= 1.0) {
      send_lease("grant", id, l.attempt, l.worker, &l.launch);  // the grant may have been lost
      l.last_grant = now;
    }
  }
  for (const auto id : expired) {
    const Lease l = leases_.at(id);
    release_hold(leases_.find(id));
    book_.close(id, l.attempt, LeaseState::kExpired);
    end_lease("revoke", id, l.attempt, l.worker);  // in case the worker is alive but was cut off
    const auto w = workers_.find(l.worker);
    const std::string host = w == workers_.end() ? l.worker : w->second.host;
    log::warn("lease " + lease_id(id, l.attempt) + " of " + host + " not renewed for " +
              std::to_string(static_cast<int>(options_.lease_ttl_s)) + " s");
    sink.on_failure(id, l.attempt, "worker " + host + " stopped renewing its lease");
  }
}

void LeaseLauncher::end_lease(const std::string& action, bus::EpisodeId id, int attempt, const std::string& worker) {
  unsent_ends_.push_back({action, id, attempt, worker});
}

void LeaseLauncher::flush_book() {
  book_.flush();
  for (const auto& [id, attempt] : unsent_grants_) {
    const auto it = leases_.find(id);
    if (it != leases_.end() && it->second.attempt == attempt) {
      send_lease("grant", id, attempt, it->second.worker, &it->second.launch);
    }
  }
  unsent_grants_.clear();
  for (const LeaseEnd& e : unsent_ends_) {
    send_lease(e.action, e.episode, e.attempt, e.worker);
    if (leases_.count(e.episode) == 0) stamp_.forget_episode(e.episode);
  }
  unsent_ends_.clear();
}

void LeaseLauncher::poll(int timeout_ms, LaunchSink& sink) {
  sink_ = &sink;
  flush_book();  // what launch() and drop() wrote since the last poll, in one commit, then sent
  if (bus_.handle_once(timeout_ms)) {
    while (bus_.handle_once(0)) {
    }
  }
  mark_silent_workers();
  expire_leases(sink);
  for (const auto& died : supervisor_.poll()) log::warn(died + " restarted");
  if (Clock::now() >= next_announce_) {
    announce("running");
    next_announce_ = Clock::now() + std::chrono::seconds(1);
  }
  flush_book();  // what this round closed, then the releases and revocations
  sink_ = nullptr;
}

void LeaseLauncher::announce(const std::string& state, const std::string& echo) {
  mtg::run_info_t m = announcement(run_, counts_);
  m.echo = echo;
  m.header = stamp_.next({}, 0, "run_info");
  m.state = state;
  m.session = session_;
  m.heard = heard_sessions();
  m.n_heard = static_cast<std::int16_t>(m.heard.size());
  m.lease_ttl_ms = static_cast<std::int32_t>(options_.lease_ttl_s * 1000.0);
  m.workers = live_workers();
  m.recordings = options_.recordings.to_string();
  const auto now = Clock::now();
  while (!finish_times_.empty() && seconds_between(finish_times_.front(), now) > 60.0) finish_times_.pop_front();
  m.episodes_per_min = static_cast<double>(finish_times_.size());
  // The dataset fingerprints are long: in one announcement of five, and in the one that first
  // names a new worker; the digest is in all. (A worker keeps the last fingerprints it heard of
  // a session, and joins from any announcement that names it.)
  if (announcements_++ % 5 != 0 && !fingerprints_due_) m.dataset_json.clear();
  fingerprints_due_ = false;
  bus_.publish(bus::kRunInfo, m);
}

void LeaseLauncher::remember_delivered(const AttemptKey& key) {
  if (!delivered_.insert(key).second) return;
  delivered_order_.push_back(key);
  if (delivered_order_.size() > kDeliveredKept) {
    delivered_.erase(delivered_order_.front());
    delivered_order_.pop_front();
  }
}

std::vector<std::string> LeaseLauncher::heard_sessions() {
  const auto now = Clock::now();
  std::erase_if(heard_, [&](const auto& h) { return seconds_between(h.second, now) > options_.lease_ttl_s; });
  while (heard_.size() > kHeardKept) {
    heard_.erase(std::min_element(heard_.begin(), heard_.end(),
                                  [](const auto& a, const auto& b) { return a.second < b.second; }));
  }
  std::vector<std::string> out;
  for (const auto& [session, at] : heard_) out.push_back(session);
  return out;
}

void LeaseLauncher::close() {
  flush_book();
  // Workers leave the run when they hear it is done; say it a few times (UDP). With leases still
  // out (interrupted) say nothing: the workers finish them, and a resumed coordinator adopts them.
  for (int i = 0; i < 3 && leases_.empty(); ++i) {
    announce("done");
    bus_.handle_once(100);
  }
  if (governor_) supervisor_.stop("governor", SIGTERM, 3000);
  if (bus_.rejected() > 0) {
    log::warn(std::to_string(bus_.rejected()) +
              " message(s) on the shared bus had no valid signature (another key, or none) and were dropped");
  }
  if (bus_.replayed() > 0) {
    log::warn(std::to_string(bus_.replayed()) +
              " signed message(s) on the shared bus were replays (taken before) and were dropped");
  }
}

}  // namespace mtg::orchestrator::remote
