#pragma once
// Messages on a bus shared between hosts are authenticated (docs/multihost.md, "Threat model"):
// each carries, after its LCM encoding, the sender's session nonce (16 random bytes drawn when
// the authenticator is made, i.e. at every process start), its number in that session (8 bytes,
// big-endian, from 1) and a 32-byte HMAC-SHA-256 over its channel, bytes, nonce and number, keyed
// per run with a secret every host reads from the same key file. LCM decoders ignore trailing
// bytes, so stock lcm-spy and lcm-logger still read every message. A message whose tag does not
// hold (unsigned, forged, or from a host without the key) is dropped and counted, never handled;
// so is one this receiver has taken before (a replay, replay_window.h).
//
// Keys: K_run = HMAC(secret, "mtg-bus-run:" + run id), where the run id is the one in the
// message's header ("" for messages outside a run), so a message of one run never passes for
// another's. What an attacker on the segment can still do is listed in docs/multihost.md.

#include <openssl/types.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bus/replay_window.h"
#include "core/util/memo_table.h"

namespace mtg::bus {

class Authenticator {
 public:
  /// Bytes of the tag appended to every message.
  static constexpr std::size_t kTagBytes = 32;
  /// Bytes appended in all: nonce, number, tag.
  static constexpr std::size_t kTrailerBytes = ReplayWindow::kNonceBytes + 8 + kTagBytes;

  explicit Authenticator(std::string secret);
  /// A key file's secret: its contents, surrounding whitespace removed.
  /// @throws mtg::Error naming the file when it is missing, unreadable, or shorter than 16 bytes.
  static std::string read_secret(const std::filesystem::path& file);

  /// `payload` with this session's nonce, the next number and the tag appended.
  std::vector<std::uint8_t> sign(const std::string& channel, std::span<const std::uint8_t> payload) const;
  /// The payload (without its trailer) when the tag holds and the message is new to this
  /// receiver; nullopt otherwise, counted in rejected() or replayed(). `delivery` identifies the
  /// received datagram (its receive time): the same one handed to a second subscription passes.
  std::optional<std::span<const std::uint8_t>> verify(const std::string& channel, std::span<const std::uint8_t> message,
                                                      std::int64_t delivery = -1) const;
  /// Messages dropped by verify() so far for a tag that does not hold.
  std::int64_t rejected() const { return rejected_; }
  /// Messages with a valid tag dropped as taken before (or older than the window of their session).
  std::int64_t replayed() const { return replayed_; }
  /// Run keys held now (at most kRunKeysKept, whatever run ids the traffic names).
  std::size_t run_keys_kept() const { return run_keys_.size(); }

 private:
  std::vector<std::uint8_t> tag(const std::string& channel, std::span<const std::uint8_t> payload,
                                std::span<const std::uint8_t> trailer) const;
  std::vector<std::uint8_t> run_key(const std::string& run_id) const;

  std::string secret_;
  std::shared_ptr<EVP_MAC> mac_;  // OpenSSL's HMAC implementation
  // Bounded: any run id in any datagram (unsigned junk included) is derived once and kept, so
  // without a bound the table grew with every id an attacker sent.
  static constexpr std::size_t kRunKeysKept = 64;
  mutable BoundedMemoTable<std::vector<std::uint8_t>> run_keys_{kRunKeysKept};
  mutable std::atomic<std::int64_t> rejected_{0};
  mutable std::atomic<std::int64_t> replayed_{0};
  ReplayWindow::Nonce session_{};
  mutable std::atomic<std::uint64_t> sent_{0};
  mutable ReplayWindow taken_;
};

/// A fresh session token: 16 random bytes (OpenSSL), hex. Coordinators and workers draw one when
/// they start and name it in their messages, so a message of an earlier process never passes for
/// one of this one. @throws mtg::Error when OpenSSL cannot draw.
std::string draw_session_token();

/// The key file of a shared bus: `key_file` if given, else $MTG_BUS_KEY.
/// @throws mtg::Error with the fix when there is neither.
std::string shared_bus_key_file(const std::string& key_file);
/// Writes a fresh secret (32 random bytes from OpenSSL, hex) to `file`, readable by its owner
/// only, unless the file exists. @throws mtg::Error when it cannot be written.
void create_key_file(const std::filesystem::path& file);
/// The authenticator of that key file. @throws mtg::Error as above, or naming an unusable file.
std::shared_ptr<const Authenticator> shared_bus_authenticator(const std::string& key_file);

}  // namespace mtg::bus
