#pragma once
// One episode attempt's recording as it travels from a worker to the coordinator: the messages
// of that attempt on the worker's bus, as LCM event-log bytes (the .lcmlog format, so the
// coordinator stores them as they are and lcm::LogFile reads them), cut into chunks that each
// fit one datagram, and put back together with a size and checksum check.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "mtg/header_t.hpp"
#include "mtg/record_chunk_t.hpp"

namespace mtg::orchestrator::remote {

struct LoggedEvent {
  std::string channel;
  std::int64_t utime = 0;  // receive time on the worker (lcm-logplayer paces by it)
  std::vector<std::uint8_t> data;
};

/// The header_t every mtg message carries first (after LCM's 8-byte type fingerprint); nullopt
/// for bytes that do not start with one.
std::optional<mtg::header_t> peek_header(std::span<const std::uint8_t> message);

/// The events in LCM's event-log format, numbered from 0.
std::vector<std::uint8_t> encode_event_log(const std::vector<LoggedEvent>& events);
/// @throws mtg::Error naming `origin` on a truncated or malformed log.
std::vector<LoggedEvent> decode_event_log(std::span<const std::uint8_t> bytes, const std::string& origin);

/// Chunks of at most `chunk_bytes` each (at least one, even for an empty log), stamped with
/// `header` (the attempt) and `lease_id`.
std::vector<mtg::record_chunk_t> make_chunks(const mtg::header_t& header, const std::string& lease_id,
                                             std::span<const std::uint8_t> log, int chunk_bytes);

/// Collects the chunks of one recording in any order, duplicates included.
class ChunkAssembly {
 public:
  /// @throws mtg::Error when the chunk contradicts the ones before (count, size or checksum).
  void add(const mtg::record_chunk_t& chunk);
  bool complete() const;
  /// The whole log. @throws mtg::Error if incomplete or the size or checksum is wrong.
  std::vector<std::uint8_t> bytes() const;
  int received() const { return received_; }
  int count() const { return count_; }

 private:
  int count_ = -1;
  std::int64_t total_ = 0;
  std::int64_t checksum_ = 0;
  int received_ = 0;
  std::vector<std::optional<std::vector<std::uint8_t>>> parts_;
};

}  // namespace mtg::orchestrator::remote
