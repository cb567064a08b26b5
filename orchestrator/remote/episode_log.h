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

#include "bus/event_log.h"
#include "bus/header.h"
#include "mtg/header_t.hpp"
#include "mtg/record_chunk_t.hpp"

namespace mtg::orchestrator::remote {

using bus::decode_event_log;
using bus::encode_event_log;
using bus::LoggedEvent;
using bus::peek_header;

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
  int count() const { return count_; }

 private:
  int count_ = -1;
  std::int64_t total_ = 0;
  std::int64_t checksum_ = 0;
  int received_ = 0;
  std::vector<std::optional<std::vector<std::uint8_t>>> parts_;
};

}  // namespace mtg::orchestrator::remote
