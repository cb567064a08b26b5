#pragma once
// Typed publish/subscribe over LCM. One Bus per process thread; callbacks run inside
// handle_*() on the calling thread, in subscription order (LCM semantics).
//
// Backends come from the URL: udpm:// (real processes, one host or several), memq:// (in-process
// tests), file://<log>?speed=0 (re-driving services from a recording as fast as possible).

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "bus/authenticator.h"
#include "bus/channel_filter.h"
#include "bus/private_network.h"
#include "bus/truth_seal.h"
#include "core/util/error.h"
#include "mtg/episode_truth_t.hpp"
#include "mtg/header_t.hpp"

namespace mtg::bus {

/// Messages a subscription may queue before LCM drops them silently (its default is 30).
inline constexpr int kQueueCapacity = 10000;

class Bus {
 public:
  /// Connects to `url` (normalised; udpm URLs are refused without a proper multicast route).
  /// With `network`, the bus's sockets are made in that namespace (private_network.h): the bus
  /// is the one of the processes started inside it, and nothing outside it reaches.
  /// @throws mtg::Error naming the URL and the fix when LCM cannot start.
  explicit Bus(const std::string& url, std::shared_ptr<const PrivateNetwork> network = nullptr);
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  /// From now on every message published is signed and every message received must carry a
  /// valid tag (authenticator.h): for a bus shared between hosts. Call before subscribing.
  void authenticate(std::shared_ptr<const Authenticator> auth) { auth_ = std::move(auth); }
  /// From now on episode answers (episode_truth_t) this process publishes are sealed with
  /// `seal` and those it receives are opened with it (truth_seal.h); one that does not open, or
  /// comes unsealed, is dropped and counted. Call before subscribing. Without a seal, sealed
  /// answers arrive sealed.
  void seal_truths(std::shared_ptr<const TruthSeal> seal) { seal_ = std::move(seal); }
  /// Sealed answers that did not open with this bus's seal.
  std::int64_t unopened() const { return *unopened_; }

  /// Messages dropped for a missing or wrong tag (0 without authentication).
  std::int64_t rejected() const { return auth_ ? auth_->rejected() : 0; }
  /// Signed messages dropped as replays: taken before by this bus (0 without authentication).
  std::int64_t replayed() const { return auth_ ? auth_->replayed() : 0; }
  /// Typed messages dropped because their header's schema_version is not this build's
  /// (bus/header.h kSchemaVersion): a process of another mtg version on the same bus.
  std::int64_t foreign_schema() const { return schema_gate_.dropped; }

  /// @throws mtg::Error if LCM reports a failure (e.g. the message exceeds the UDP limits).
  template <class Msg>
  void publish(const std::string& channel, const Msg& msg) {
    if constexpr (std::is_same_v<Msg, mtg::episode_truth_t>) {
      if (seal_ && !is_sealed(msg)) return publish(channel, seal_->seal(msg));
    }
    if (auth_) {
      std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
      msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
      publish_raw(channel, bytes);
      return;
    }
    if (lcm_->publish(channel, &msg) != 0) publish_failed(channel);
  }

  /// Publishes already encoded bytes (forwarding a message between buses unchanged; signed on an
  /// authenticated bus).
  void publish_raw(const std::string& channel, std::span<const std::uint8_t> data) {
    std::vector<std::uint8_t> signed_bytes;
    if (auth_) {
      signed_bytes = auth_->sign(channel, data);
      data = signed_bytes;
    }
    if (lcm_->publish(channel, data.data(), static_cast<unsigned int>(data.size())) != 0) publish_failed(channel);
  }

  /// Calls `handler(channel, msg)` for every message on channels matching `channel_regex`.
  /// Messages that do not decode as Msg are skipped by LCM. An exception from a handler is
  /// rethrown by the handle_*() call that dispatched it (never through LCM's C frames).
  template <class Msg>
  void subscribe(const std::string& channel_regex,
                 std::function<void(const std::string&, const Msg&)> handler) {
    if constexpr (std::is_same_v<Msg, mtg::episode_truth_t>) {
      if (seal_) {
        handler = [fn = std::move(handler), seal = seal_, unopened = unopened_](const std::string& channel,
                                                                               const Msg& m) {
          std::optional<Msg> opened;
          try {
            // Sealing also proves who wrote them: answers in clear could come from anyone.
            if (!is_sealed(m)) {
              throw Error("the answers of episode " + std::to_string(m.header.episode_id) + " came unsealed");
            }
            opened = seal->open(m);
          } catch (const Error& e) {
            if ((*unopened)++ == 0) log_unopened(e.what());
            return;
          }
          fn(channel, *opened);
        };
      }
    }
    if (auth_) {  // verified bytes first (subscribe_raw), then decoded
      subscribe_raw(channel_regex, [fn = std::move(handler), gate = &schema_gate_](const std::string& channel,
                                                             std::span<const std::uint8_t> bytes, std::int64_t) {
        Msg m{};
        if (m.decode(bytes.data(), 0, static_cast<int>(bytes.size())) >= 0 && gate->admit(m, channel)) fn(channel, m);
      });
      return;
    }
    auto owned = std::make_unique<Handler<Msg>>(std::move(handler), pending_, schema_gate_);
    lcm::Subscription* sub = lcm_->subscribe(channel_regex, &Handler<Msg>::on, owned.get());
    if (sub == nullptr) throw Error("LCM subscribe failed for " + channel_regex);
    sub->setQueueCapacity(kQueueCapacity);
    handlers_.push_back(std::move(owned));
    filter_channels(channel_regex);
  }

  /// Like subscribe(), undecoded: `handler(channel, bytes, receive time in µs)`; on an
  /// authenticated bus only verified messages arrive, without their tag.
  void subscribe_raw(const std::string& channel_regex,
                     std::function<void(const std::string&, std::span<const std::uint8_t>, std::int64_t)> handler);

  /// Dispatches queued messages for up to `timeout_ms`; returns true if one was handled.
  /// For file:// URLs returns false at the end of the log.
  bool handle_once(int timeout_ms);
  /// Handles messages until `done()` or `timeout_ms` elapse; returns done().
  bool handle_until(const std::function<bool()>& done, int timeout_ms);

  int fileno() { return lcm_->getFileno(); }
  const std::string& url() const { return url_; }
  /// On udpm: whether the kernel drops, before this process wakes, the messages of channels it
  /// did not subscribe to (bus/channel_filter.h). False until a subscription names only channels,
  /// or when liblcm's receive socket could not be told apart from another.
  bool filters_channels() const { return filtered_; }

 private:
  void tune_tcp();
  // Everything of the constructor that makes or names sockets.
  void connect();
  // This process's sockets on the bus's port that were not open before the bus was made.
  std::vector<OpenSocket> sockets_opened() const;
  // After a subscription on udpm: the receive socket's filter lets through what is now subscribed.
  void filter_channels(const std::string& subscription);
  // Drops typed messages of another schema version, saying so once per bus.
  struct SchemaGate {
    std::int64_t dropped = 0;
    bool warned = false;
    bool admit_header(const mtg::header_t& header, const std::string& channel);
    template <class Msg>
    bool admit(const Msg& msg, const std::string& channel) {
      if constexpr (requires { msg.header.schema_version; }) return admit_header(msg.header, channel);
      return true;
    }
  };

  struct HandlerBase {
    virtual ~HandlerBase() = default;
  };
  template <class Msg>
  struct Handler : HandlerBase {
    Handler(std::function<void(const std::string&, const Msg&)> f, std::exception_ptr& pending, SchemaGate& g)
        : fn(std::move(f)), pending_error(pending), gate(g) {}
    // Unwinding through liblcm would leave its receive buffers half-released (it aborts in
    // lcm_destroy), so the exception waits here until LCM has returned.
    void on(const lcm::ReceiveBuffer*, const std::string& channel, const Msg* msg) {
      if (pending_error || !gate.admit(*msg, channel)) return;
      try {
        fn(channel, *msg);
      } catch (...) {
        pending_error = std::current_exception();
      }
    }
    std::function<void(const std::string&, const Msg&)> fn;
    std::exception_ptr& pending_error;
    SchemaGate& gate;
  };

  struct RawHandler : HandlerBase {
    using Fn = std::function<void(const std::string&, std::span<const std::uint8_t>, std::int64_t)>;
    RawHandler(Fn f, std::exception_ptr& pending, std::shared_ptr<const Authenticator> a)
        : fn(std::move(f)), pending_error(pending), auth(std::move(a)) {}
    void on(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
      if (pending_error) return;
      try {
        std::span<const std::uint8_t> bytes(static_cast<const std::uint8_t*>(rbuf->data), rbuf->data_size);
        if (auth) {
          const auto verified = auth->verify(channel, bytes, rbuf->recv_utime);
          if (!verified) return;  // counted by the authenticator
          bytes = *verified;
        }
        fn(channel, bytes, rbuf->recv_utime);
      } catch (...) {
        pending_error = std::current_exception();
      }
    }
    Fn fn;
    std::exception_ptr& pending_error;
    std::shared_ptr<const Authenticator> auth;
  };

  void rethrow_pending();
  /// @throws mtg::Error naming the channel, or the lost hub on a tcpq bus.
  [[noreturn]] void publish_failed(const std::string& channel) const;
  /// The line for a tcpq bus whose hub went away, `doing` what ("" or " while ...").
  std::string hub_lost(const std::string& doing) const;

  std::string url_;
  bool is_log_ = false;
  bool tcp_ = false;  // a tcpq bus (LCM hub)
  bool end_of_log_ = false;
  std::unique_ptr<lcm::LCM> lcm_;
  std::exception_ptr pending_;
  std::vector<std::unique_ptr<HandlerBase>> handlers_;
  std::shared_ptr<const Authenticator> auth_;
  std::shared_ptr<const TruthSeal> seal_;
  std::shared_ptr<std::int64_t> unopened_ = std::make_shared<std::int64_t>(0);
  static void log_unopened(const std::string& why);  // the first one, as a warning
  SchemaGate schema_gate_;
  // udpm only: liblcm opens its receive socket at the first subscription (in a private network,
  // when the bus is made); it is the one socket on the bus's port that was not open before.
  int udpm_port_ = 0;
  std::vector<OpenSocket> sockets_before_;
  OpenSocket receive_socket_;
  ChannelFilter channels_;
  bool filtered_ = false;
};

}  // namespace mtg::bus
