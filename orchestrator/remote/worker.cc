#include "orchestrator/remote/worker.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <deque>
#include <fstream>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/error_events.h"
#include "bus/header.h"
#include "bus/host_bus.h"
#include "bus/private_network.h"
#include "bus/url.h"
#include "bus/process/heartbeat.h"
#include "bus/process/identity.h"
#include "bus/process/stop_signals.h"
#include "core/episode/outcomes.h"
#include "core/scene/dataset.h"
#include "core/scene/dataset_fingerprint.h"
#include "bus/recording_ref.h"
#include "core/util/file_bytes.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/log.h"
#include "agents/vlm/http_relay.h"
#include "mtg/lease_renewal_t.hpp"
#include "mtg/lease_t.hpp"
#include "mtg/recording_request_t.hpp"
#include "mtg/run_control_t.hpp"
#include "mtg/run_info_t.hpp"
#include "orchestrator/remote/episode_log.h"
#include "orchestrator/remote/recordings_place.h"
#include "orchestrator/remote/run_announcement.h"
#include "orchestrator/remote/session_rules.h"
#include "orchestrator/run/local_runtime.h"
#include "orchestrator/run/run_namespace.h"

namespace mtg::orchestrator::remote {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Forwards one channel between two buses unchanged. Each bus echoes what is published on it
// back to its own subscribers, so a forwarded message is remembered and not sent back.
class Bridge {
 public:
  bool should_forward(std::span<const std::uint8_t> bytes) {
    const std::uint64_t h = fnv1a64(bytes);
    const auto it = echoes_.find(h);
    if (it != echoes_.end()) {
      echoes_.erase(it);
      return false;
    }
    if (echoes_.size() > 10000) echoes_.clear();  // echoes lost for good
    echoes_.insert(h);
    return true;
  }

 private:
  std::multiset<std::uint64_t> echoes_;
};

class Worker final : public LaunchSink {
 public:
  Worker(WorkerOptions options, std::shared_ptr<const bus::PrivateNetwork> network)
      : options_(std::move(options)), network_(std::move(network)),
        host_(options_.name.empty() ? process::host_name() : options_.name),
        shared_(options_.bus_url), stamp_("", process::sender_id("worker")) {
    if (options_.capacity < 1) throw Error("mtg worker: --capacity must be at least 1");
    shared_.authenticate(bus::shared_bus_authenticator(options_.bus_key));
    shared_.subscribe<mtg::run_info_t>(bus::kRunInfo, [this](const std::string&, const mtg::run_info_t& m) {
      on_run_info(m);
    });
    // Grants, releases and revocations come on this worker's own channel.
    shared_.subscribe<mtg::lease_t>(bus::lease_channel(session_), [this](const std::string&, const mtg::lease_t& m) {
      if (m.worker == stamp_.sender() && !run_id_.empty() && m.header.run_id == run_id_) on_lease(m);
    });
    // `mtg status` asks (a signed challenge); the answer is a beat that names it, so a status
    // believes no beat sent before it asked (a dead worker's, replayed).
    shared_.subscribe<mtg::run_control_t>(bus::kControl, [this](const std::string&, const mtg::run_control_t& m) {
      if (const auto nonce = status_challenge(m.command, m.argument)) heartbeat(*nonce);
    });
    shared_.subscribe<mtg::recording_request_t>(bus::kRecordRequest, [this](const std::string&,
                                                                           const mtg::recording_request_t& m) {
      if (m.host.empty() || m.host == host_) on_recording_request(m);
    });
    shared_.subscribe_raw(bus::kRateLimit, [this](const std::string& channel, std::span<const std::uint8_t> bytes,
                                                  std::int64_t) {
      if (runtime_ && rate_bridge_.should_forward(bytes)) runtime_->bus().publish_raw(channel, bytes);
    });
  }

  int run() {
    process::install_stop_signals();
    const auto started = Clock::now();
    log::info(stamp_.sender() + " on " + options_.bus_url + " (host bus " + options_.local_url +
              (network_ ? " in a network namespace of its own" : "") + "), capacity " +
              std::to_string(options_.capacity));
    auto next_beat = Clock::now();
    auto next_renewal = Clock::now();
    while (!process::stop_signal_received()) {
      wait_for_messages(sending() ? 10 : 20);  // a paced recording goes on after at most 10 ms
      while (shared_.handle_once(0)) {
      }
      if (abandoned()) {
        log::warn("no announcement of run " + run_id_ + " for 2 minutes; leaving it");
        leave_ = true;
      }
      if (leave_) leave();
      if (once_done_) break;
      if (!options_.run_id.empty() && !heard_run_ &&
          Clock::now() - started > std::chrono::duration<double>(kRunNotHeardS)) {
        log::error("run " + options_.run_id + " was not announced on " + options_.bus_url + " within " +
                   std::to_string(static_cast<int>(kRunNotHeardS)) + " s; is its coordinator running there?");
        return 1;
      }
      if (join_) join();
      if (runtime_) {
        runtime_->poll(0, *this);
        finalize_finished();
      }
      send_outbox();
      const auto now = Clock::now();
      if (now >= next_beat || beat_now_) {
        beat_now_ = false;
        heartbeat();
        next_beat = now + std::chrono::milliseconds(500);
      }
      if (now >= next_renewal) {
        renew_all();
        next_renewal = now + std::chrono::seconds(1);
      }
    }
    status_ = process::HeartbeatStatus::kDraining;
    heartbeat();
    if (runtime_) runtime_->close();
    return 0;
  }

  // LaunchSink: what became of the attempts on this host. Finished attempts are shipped after
  // poll() returns, so the recording also holds the message that finished them.
  void on_result(const mtg::episode_result_t& m, const std::string&, const bus::RecordingRef*) override {
    finished_.push_back(m);
  }

  void on_failure(bus::EpisodeId episode_id, int attempt, const std::string& why) override {
    const auto it = held_.find(episode_id);
    if (it == held_.end() || it->second.attempt != attempt) return;
    mtg::episode_result_t m{};
    m.header = stamp_.next(episode_id, attempt, "result");
    m.task_id = it->second.task_id;
    m.agent = it->second.agent;
    m.stage = episode::to_string(episode::Stage::kStart);
    m.cause = episode::to_string(episode::Cause::kTransportError);  // not the agent's: the coordinator tries again
    m.detail = "on " + host_ + ": " + why;
    finished_.push_back(m);
  }

  void on_agent_stopped(const std::string& agent, const std::string& why) override {
    mtg::error_event_t m = bus::agent_stopped_event(agent, why);
    m.header = stamp_.next({}, 0, "error");
    shared_.publish(bus::kError, m);
  }

 private:
  struct Held {
    int attempt = 0;
    std::string task_id, agent;
  };
  struct Outgoing {
    mtg::episode_result_t result{};
    std::optional<mtg::recording_ref_t> ref;  // the recording stayed here: only this goes
    std::vector<mtg::record_chunk_t> chunks;
    std::size_t next = 0;              // next chunk to send
    bool resent = false;
    Clock::time_point resend_at;       // after everything went out: send it all again unless released
  };

  // Sleeps until either bus has a message (or `timeout_ms`): a grant must not wait for the
  // host bus to go quiet, nor a result for the shared one.
  void wait_for_messages(int timeout_ms) {
    pollfd fds[2] = {{shared_.fileno(), POLLIN, 0}, {runtime_ ? runtime_->bus().fileno() : -1, POLLIN, 0}};
    ::poll(fds, runtime_ ? 2 : 1, timeout_ms);
  }

  std::string lease_id(bus::EpisodeId episode_id, int attempt) const {
    return run_id_ + "/" + to_string(episode_id) + "/" + std::to_string(attempt);
  }

  void on_run_info(const mtg::run_info_t& m) {
    if (!options_.run_id.empty() && m.header.run_id != options_.run_id) return;
    heard_run_ = true;
    const HeardAnnouncement heard{m.header.run_id, m.session, m.state == "done", m.heard};
    if (!m.dataset_json.empty()) fingerprints_ = {m.session, m.dataset_json};
    switch (sessions_.hear(heard, session_, join_ ? join_->header.run_id : run_id_,
                           join_ ? join_->session : serving_, options_.run_id)) {
      case OnAnnouncement::kIgnore:
        return;
      case OnAnnouncement::kUnnamed:
        beat_now_ = true;  // so the coordinator names this worker in its next announcement
        return;
      case OnAnnouncement::kJoin: {
        // A run this host could not start is tried again after a while, not on every announcement.
        if (m.header.run_id == failed_run_ && Clock::now() < retry_join_at_) return;
        // Join with the fingerprints: those this session sent earlier, else wait for them.
        const bool without_fingerprints = !m.dataset_digest.empty() && m.dataset_json.empty();
        if (without_fingerprints && fingerprints_.first != m.session) return;
        join_ = m;
        if (without_fingerprints) join_->dataset_json = fingerprints_.second;
        return;
      }
      case OnAnnouncement::kFollow:
        if (join_) return;  // still starting: the run's services come up for the session joined
        log::info("run " + run_id_ + " goes on under a new coordinator session (" + m.header.sender + ")");
        sessions_.left(serving_);
        serving_ = m.session;
        [[fallthrough]];
      case OnAnnouncement::kStay:
        last_announcement_ = Clock::now();
        return;
      case OnAnnouncement::kLeave:
        if (join_) {
          join_.reset();  // over before this host started it
        } else {
          leave_ = true;
        }
        return;
    }
  }

  // A run whose coordinator is gone for good: nothing held, nothing to deliver, no announcement
  // for a long time. (A coordinator that comes back finds its results in the outbox meanwhile.)
  bool abandoned() const {
    return runtime_ && held_.empty() && outbox_.empty() && Clock::now() - last_announcement_ > std::chrono::minutes(2);
  }

  void join() {
    const mtg::run_info_t info = *join_;
    join_.reset();
    run_id_ = info.header.run_id;
    serving_ = info.session;
    stamp_.set_run_id(run_id_);
    last_announcement_ = Clock::now();
    status_ = process::HeartbeatStatus::kStarting;
    heartbeat();
    log::info("joining run " + run_id_ + " of " + info.header.sender);
    try {
      RuntimeConfig c = announced_config(info);
      c.bus_url = options_.local_url;
      c.network = network_;
      c.vlm_args.insert(c.vlm_args.end(), options_.vlm_args.begin(), options_.vlm_args.end());
      c.parallel = options_.capacity;
      c.recorder = options_.recorder;
      c.renderers = options_.renderers;
      c.governor = false;  // the coordinator's governor serves every host
      // The answers come sealed in the grants; this host's judge opens them with the key every
      // host derives from the bus secret.
      c.truth_secret_file = bus::shared_bus_key_file(options_.bus_key);
      check_dataset(c);
      use_recordings(info);
      runtime_ = std::make_unique<LocalRuntime>(c, fs::path(options_.dir) / run_id_);
      runtime_->bus().subscribe_raw(".*", [this](const std::string& channel, std::span<const std::uint8_t> bytes,
                                                 std::int64_t utime) { capture(channel, bytes, utime); });
      runtime_->bus().subscribe_raw(bus::kRateLimit, [this](const std::string& channel,
                                                            std::span<const std::uint8_t> bytes, std::int64_t) {
        if (rate_bridge_.should_forward(bytes)) shared_.publish_raw(channel, bytes);
      });
      runtime_->open();
      // For `scripts/lcm-spy --run <dir>/<run id>`.
      write_bus_file(fs::path(options_.dir) / run_id_, options_.local_url, network_.get());
      status_ = process::HeartbeatStatus::kReady;
    } catch (const Error& e) {
      log::error("cannot run " + run_id_ + ": " + e.what() + " (trying again in 30 s)");
      // The coordinator says why this host stays out.
      mtg::error_event_t m = bus::error_event(stamp_.sender(), bus::Severity::kFailure,
                                              "worker on " + host_ + " cannot run " + run_id_ + ": " + e.what());
      m.header = stamp_.next({}, 0, "error");
      shared_.publish(bus::kError, m);
      failed_run_ = run_id_;
      retry_join_at_ = Clock::now() + std::chrono::seconds(30);
      runtime_.reset();
      run_id_.clear();
      serving_.clear();
      stamp_.set_run_id("");
      status_ = process::HeartbeatStatus::kIdle;
    }
  }

  // This host's dataset must be the one the run's task set was made from (run_info_t).
  void check_dataset(const RuntimeConfig& c) const {
    if (c.dataset_json.empty()) return;
    // Where this host will load scenes from: its own --data, else the path the episodes name.
    const fs::path root = scene::resolve_data_root(options_.data_dir.empty() ? c.data_dir : options_.data_dir);
    const std::string diff = scene::first_difference(scene::fingerprints_from_json(nlohmann::json::parse(c.dataset_json)), root);
    if (diff.empty()) return;
    const std::string what = "the dataset at " + root.string() + " is not the one the run's tasks were made from (" + diff + ")";
    if (!c.allow_data_mismatch) throw Error(what);
    log::warn(what + "; going on (the run allows it)");
  }

  // Where this run's recordings go (run_info_t.recordings): to the coordinator (""), into a folder
  // every host shares, or kept in this worker's folder. A shared folder must be the coordinator's:
  // its probe file must be readable here, with the coordinator session's token in it.
  void use_recordings(const mtg::run_info_t& info) {
    recordings_ = parse_recordings_place(info.recordings);
    switch (recordings_.kind) {
      case RecordingsPlace::Kind::kCoordinator:
        return;
      case RecordingsPlace::Kind::kWorker:
        recordings_folder_ = fs::absolute(fs::path(options_.dir) / run_id_ / "episodes");
        return;
      case RecordingsPlace::Kind::kShared:
        break;
    }
    const fs::path root = recordings_.run_folder(run_id_);
    const fs::path probe = root / kSharedProbe;
    std::ifstream in(probe);
    std::string token;
    std::getline(in, token);
    if (!in && token.empty()) {
      throw Error("the shared recordings folder " + root.string() + " is not shared with this host (" + probe.string() +
                  " cannot be read here); mount it at the same path on every host");
    }
    if (token != info.session) {
      throw Error("the shared recordings folder " + root.string() + " here is not the coordinator's (" + probe.string() +
                  " names another session); mount the same folder at the same path on every host");
    }
    recordings_folder_ = root;
  }

  void leave() {
    leave_ = false;
    if (shared_.rejected() > 0) {
      log::warn(std::to_string(shared_.rejected()) + " message(s) on the shared bus had no valid signature and were dropped");
    }
    if (shared_.replayed() > 0) {
      log::warn(std::to_string(shared_.replayed()) + " signed message(s) on the shared bus were replays and were dropped");
    }
    if (runtime_) runtime_->close();
    runtime_.reset();
    log::info("run " + run_id_ + " is done");
    held_.clear();
    outbox_.clear();
    captured_.clear();
    run_id_.clear();
    serving_.clear();
    stamp_.set_run_id("");
    status_ = process::HeartbeatStatus::kIdle;
    once_done_ = options_.once;
  }

  void heartbeat(const std::string& echo = "") {
    mtg::heartbeat_t hb = process::heartbeat_message(
        {"worker", host_, options_.capacity, static_cast<int>(held_.size()), tick_++, status_});
    hb.header = stamp_.next({}, 0, "heartbeat");
    hb.session = session_;
    hb.serving = serving_;
    hb.echo = echo;
    shared_.publish(bus::kHeartbeat, hb);
  }

  void send_lease(const std::string& action, bus::EpisodeId episode_id, int attempt) {
    mtg::lease_t m{};
    m.header = stamp_.next(episode_id, attempt, "lease");
    m.lease_id = lease_id(episode_id, attempt);
    m.worker = stamp_.sender();
    m.action = action;
    m.session = serving_;
    shared_.publish(bus::kLease, m);
  }

  // Every lease held, in one message (lease_renewal_t): one a second per worker, whatever its
  // capacity, so renewals do not grow with the leases out.
  void renew_all() {
    if (held_.empty()) return;
    mtg::lease_renewal_t m{};
    m.header = stamp_.next({}, 0, "renewal");
    m.worker = stamp_.sender();
    m.session = serving_;
    for (const auto& [id, h] : held_) {
      m.episode_ids.push_back(id.value());
      m.attempts.push_back(h.attempt);
    }
    m.n_leases = static_cast<std::int32_t>(m.episode_ids.size());
    shared_.publish(bus::kLeaseRenewal, m);
  }

  void forget(bus::EpisodeId episode_id, int attempt) {
    const auto it = held_.find(episode_id);
    if (it != held_.end() && it->second.attempt == attempt) {
      if (runtime_) runtime_->drop(episode_id, attempt);
      held_.erase(it);
    }
    captured_.erase({episode_id, attempt});
    outbox_.erase(lease_id(episode_id, attempt));
    if (held_.count(episode_id) == 0) stamp_.forget_episode(episode_id);
  }

  void on_lease(const mtg::lease_t& m) {
    const bus::EpisodeId id = bus::episode_of(m.header);
    const int attempt = m.header.attempt;
    if (m.session != serving_) return;  // an earlier coordinator session's (a replay, or late)
    if (m.action == "release" || m.action == "revoke") {
      forget(id, attempt);
      return;
    }
    if (m.action != "grant" || !runtime_ || status_ == process::HeartbeatStatus::kStarting) return;
    const auto it = held_.find(id);
    const std::optional<int> held = it == held_.end() ? std::nullopt : std::optional<int>(it->second.attempt);
    switch (hear_grant(m.session, attempt, serving_, held)) {
      case OnGrant::kIgnore:
        return;
      case OnGrant::kRenew:
        send_lease("renew", id, attempt);  // a repeated grant: our renewal was lost
        return;
      case OnGrant::kRun:
        break;
    }
    if (it != held_.end()) forget(id, it->second.attempt);  // superseded by a newer attempt
    EpisodeLaunch launch{m.start, m.truth};
    if (!options_.data_dir.empty()) launch.start.data_dir = options_.data_dir;
    held_[id] = Held{attempt, launch.start.task.task_id, launch.start.agent};
    runtime_->launch(launch);
    send_lease("renew", id, attempt);
  }

  void capture(const std::string& channel, std::span<const std::uint8_t> bytes, std::int64_t utime) {
    const auto h = peek_header(bytes);
    if (!h || h->run_id != run_id_ || !bus::episode_of(*h).valid()) return;
    const auto held = held_.find(bus::episode_of(*h));
    if (held == held_.end() || held->second.attempt != h->attempt) return;
    captured_[{bus::episode_of(*h), h->attempt}].push_back(LoggedEvent{channel, utime, {bytes.begin(), bytes.end()}});
  }

  void finalize_finished() {
    if (options_.hold_results) finished_.clear();
    for (const mtg::episode_result_t& result : finished_) {
      const bus::EpisodeId id = bus::episode_of(result.header);
      const int attempt = result.header.attempt;
      const auto held = held_.find(id);
      if (held == held_.end() || held->second.attempt != attempt) continue;  // revoked meanwhile
      const std::string lid = lease_id(id, attempt);
      std::vector<LoggedEvent> events;
      const auto c = captured_.find({id, attempt});
      if (c != captured_.end()) {
        events = std::move(c->second);
        captured_.erase(c);
      }
      const std::vector<std::uint8_t> log = encode_event_log(events);
      Outgoing out;
      out.result = result;
      if (recordings_.kind != RecordingsPlace::Kind::kCoordinator) {
        try {
          out.ref = keep_recording(id, attempt, lid, log);
        } catch (const std::exception& e) {
          // Not lost for a full or vanished folder: the coordinator keeps this one.
          log::error("cannot keep the recording of " + lid + " in " + recordings_folder_.string() + " (" + e.what() +
                     "); sending it to the coordinator instead");
        }
      }
      if (!out.ref) out.chunks = make_chunks(stamp_.next(id, attempt, "record"), lid, log, options_.chunk_bytes);
      shared_.publish(bus::kEpisodeResult, out.result);
      if (out.ref) {
        shared_.publish(bus::kRecordRef, *out.ref);
        // Sent whole (a reference has no chunks to pace): again in 3 s unless released.
        out.resend_at = Clock::now() + std::chrono::seconds(3);
      }
      outbox_[lid] = std::move(out);
    }
    finished_.clear();
  }

  bool sending() const {
    if (!gather_files_.empty() || !gather_chunks_.empty()) return true;
    for (const auto& [lid, out] : outbox_) {
      if (out.next < out.chunks.size()) return true;
    }
    return false;
  }

  // Chunks go out paced (a burst larger than the receiver's socket buffer would be lost), and
  // everything goes out again every 3 s until the coordinator releases it.
  void send_outbox() {
    int budget = options_.chunks_per_round;
    const auto now = Clock::now();
    for (auto& [lid, out] : outbox_) {
      if (out.next >= out.chunks.size()) {
        if (now < out.resend_at) continue;
        shared_.publish(bus::kEpisodeResult, out.result);
        if (out.ref) shared_.publish(bus::kRecordRef, *out.ref);
        out.next = 0;
        out.resent = true;
      }
      while (budget > 0 && out.next < out.chunks.size()) {
        const std::size_t i = out.next++;
        const int n = options_.drop_chunk_every;
        if (!out.resent && n > 0 && i % static_cast<std::size_t>(n) == static_cast<std::size_t>(n - 1)) continue;
        shared_.publish(bus::kRecord, out.chunks[i]);
        --budget;
      }
      if (out.next >= out.chunks.size()) out.resend_at = now + std::chrono::seconds(3);
      if (budget == 0) break;
    }
    // Recordings asked for by `mtg gather`, once each, paced like the rest.
    while (budget > 0 && (!gather_chunks_.empty() || !gather_files_.empty())) {
      if (gather_chunks_.empty()) {
        // The next file asked for, read only now: a long list waits as names, not as bytes.
        const GatherFile f = std::move(gather_files_.front());
        gather_files_.pop_front();
        gather_queued_.erase(f.location);
        try {
          for (auto& chunk : make_chunks(f.header, f.location, read_file_bytes(f.location), options_.chunk_bytes)) {
            gather_chunks_.push_back(std::move(chunk));
          }
        } catch (const Error& e) {
          log::warn(std::string(e.what()) + "; not sent to mtg gather");  // gone since it was asked for
        }
        continue;
      }
      shared_.publish(bus::kRecord, gather_chunks_.front());
      gather_chunks_.pop_front();
      --budget;
    }
  }

  // Where this host keeps an attempt's recording, written whole or not at all; the reference
  // that goes instead of it.
  mtg::recording_ref_t keep_recording(bus::EpisodeId id, int attempt, const std::string& lid,
                                      const std::vector<std::uint8_t>& log) {
    const fs::path file = recordings_folder_ / bus::recording_file_name(id, attempt);
    write_file_bytes_atomically(file, log);
    mtg::recording_ref_t m = bus::to_message(bus::reference_to(id, attempt, fs::absolute(file).lexically_normal().string(),
                                                               host_, recordings_.kind == RecordingsPlace::Kind::kShared, log));
    m.header = stamp_.next(id, attempt, "record_ref");
    m.lease_id = lid;
    return m;
  }

  // `mtg gather`: the recordings this host keeps (under its own folder, nothing else) go out in
  // chunks, once; the gatherer asks again for what it misses.
  void on_recording_request(const mtg::recording_request_t& m) {
    // Only the run named, and only its attempts' own files: <dir>/<run id>/episodes/E<id>-a<n>.lcmlog
    // (issue 55: a request once got any *.lcmlog under the folder, other runs' too).
    if (m.header.run_id.empty() || m.header.run_id.find('/') != std::string::npos || m.header.run_id == "." ||
        m.header.run_id == "..") {
      return;
    }
    // As keep_recording names them (absolute, lexically normal), so the two compare as paths.
    const fs::path theirs = (fs::absolute(options_.dir) / m.header.run_id / "episodes").lexically_normal();
    const std::size_t n = std::min({m.locations.size(), m.episode_ids.size(), m.attempts.size()});
    int sent = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const fs::path asked(m.locations[i]);
      const fs::path file = theirs / bus::recording_file_name(bus::EpisodeId(m.episode_ids[i]), m.attempts[i]);
      std::error_code ec;
      if (fs::absolute(asked).lexically_normal() != file || fs::is_symlink(fs::symlink_status(file, ec)) ||
          !fs::is_regular_file(fs::symlink_status(file, ec))) {
        continue;  // not a recording of that run's attempt on this host
      }
      // Asked again while still queued (the gatherer repeats what has not arrived): once is enough.
      if (!gather_queued_.insert(m.locations[i]).second) continue;
      mtg::header_t h = stamp_.next(bus::EpisodeId(m.episode_ids[i]), m.attempts[i], "gather");
      h.run_id = m.header.run_id;
      gather_files_.push_back({m.locations[i], h});
      ++sent;
    }
    if (sent > 0) log::info("sending " + std::to_string(sent) + " more kept recording(s) of run " + m.header.run_id);
  }

  WorkerOptions options_;
  std::shared_ptr<const bus::PrivateNetwork> network_;  // the host bus's (null: this host's loopback)
  std::string host_;
  bus::Bus shared_;
  bus::HeaderStamper stamp_;
  std::unique_ptr<LocalRuntime> runtime_;
  std::string run_id_;
  process::HeartbeatStatus status_ = process::HeartbeatStatus::kIdle;
  std::optional<mtg::run_info_t> join_;
  bool leave_ = false;
  bool beat_now_ = false;  // a coordinator that has not heard this worker yet announced itself
  bool once_done_ = false;
  bool heard_run_ = false;  // the run of options_.run_id has been announced
  Clock::time_point last_announcement_;
  std::string failed_run_;
  const std::string session_ = bus::draw_session_token();  // this worker process's (heartbeats)
  std::string serving_;               // the coordinator session of run_id_ ("" = none)
  CoordinatorSessions sessions_;      // ended and left ones
  std::pair<std::string, std::string> fingerprints_;  // the last dataset fingerprints heard: (session, json)
  Clock::time_point retry_join_at_;
  long tick_ = 0;
  std::map<bus::EpisodeId, Held> held_;
  std::map<std::string, Outgoing> outbox_;
  std::map<std::pair<bus::EpisodeId, int>, std::vector<LoggedEvent>> captured_;
  std::vector<mtg::episode_result_t> finished_;
  Bridge rate_bridge_;
  RecordingsPlace recordings_;        // run_info_t.recordings of the run joined
  fs::path recordings_folder_;        // where this host writes them (when not sent)
  // Kept recordings asked for by `mtg gather`: files waiting (each once), and the chunks of the
  // one being sent.
  struct GatherFile {
    std::string location;
    mtg::header_t header;
  };
  std::deque<GatherFile> gather_files_;
  std::set<std::string> gather_queued_;
  std::deque<mtg::record_chunk_t> gather_chunks_;
};

}  // namespace

int run_worker(const WorkerOptions& options) {
  WorkerOptions o = options;
  std::optional<bus::HostBusReservation> own_port;
  std::shared_ptr<const bus::PrivateNetwork> network;
  std::unique_ptr<vlm::HttpRelayServer> relay;
  if (o.local_url.empty()) {
    try {
      // First, while this process has one thread: without root it needs a user namespace.
      network = bus::PrivateNetwork::make();
      o.local_url = bus::normalize_url(bus::kDefaultUrl);
      // The model adapters inside reach no network: this process makes their calls.
      relay = std::make_unique<vlm::HttpRelayServer>();
      ::setenv(vlm::kHttpRelayEnv, relay->socket_path().c_str(), 1);
      relay->start();
    } catch (const std::exception& e) {  // mtg::Error, or a thread the relay could not start
      log::warn(std::string(e.what()) + "; the host bus is a loopback port of its own instead, which the network cannot " +
                "reach but other processes of this host can");
      network.reset();
      relay.reset();
      ::unsetenv(vlm::kHttpRelayEnv);
      own_port.emplace();
      o.local_url = own_port->url();
    }
  }
  Worker worker(std::move(o), std::move(network));
  return worker.run();
}

}  // namespace mtg::orchestrator::remote
