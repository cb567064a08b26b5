#pragma once
// Which signed messages a receiver has already taken, per sender session (docs/multihost.md,
// "Threat model"). Every process that signs draws a random session nonce when it starts and
// numbers what it sends 1, 2, 3, ...; a receiver takes each (session, number) once: a message
// it took before, or one older than the last kWindow numbers of its session, is a replay.
// A window rather than "greater than the last" because datagrams of one sender may overtake
// each other; the same datagram handed to two subscriptions of one bus is still one message.

#include <array>
#include <bitset>
#include <cstdint>
#include <map>
#include <mutex>

namespace mtg::bus {

class ReplayWindow {
 public:
  static constexpr std::size_t kNonceBytes = 16;
  static constexpr std::uint64_t kWindow = 1024;
  /// Sender sessions remembered; past this the one heard from least recently is forgotten.
  static constexpr std::size_t kSessionsKept = 256;
  using Nonce = std::array<std::uint8_t, kNonceBytes>;

  /// Whether (session, number) is new, marking it taken. `delivery` identifies one received
  /// datagram (its receive time; -1 = unknown): the same datagram seen again is still new.
  bool take(const Nonce& session, std::uint64_t number, std::int64_t delivery);

  std::size_t sessions() const;

 private:
  struct Session {
    std::uint64_t highest = 0;
    std::bitset<kWindow> taken;  // bit (n % kWindow) for n in (highest - kWindow, highest]
    std::uint64_t last_heard = 0;
  };
  mutable std::mutex mutex_;
  std::map<Nonce, Session> sessions_;
  std::uint64_t heard_ = 0;  // ordinal of the last message taken, for forgetting sessions
  struct Last {
    Nonce session{};
    std::uint64_t number = 0;
    std::int64_t delivery = -1;
  } last_;
};

}  // namespace mtg::bus
