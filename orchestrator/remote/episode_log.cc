#include "orchestrator/remote/episode_log.h"

#include <algorithm>

#include "core/util/error.h"
#include "core/util/hash.h"

namespace mtg::orchestrator::remote {
namespace {

// LCM event-log framing (lcm/eventlog.c): every event starts with this word, then big-endian
// event number, timestamp, channel length and data length.
constexpr std::uint32_t kSyncWord = 0xEDA1DA01;
constexpr std::size_t kEventHeaderBytes = 4 + 8 + 8 + 4 + 4;

void put_be(std::vector<std::uint8_t>& out, std::uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::uint64_t get_be(std::span<const std::uint8_t> in, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | in[at + static_cast<std::size_t>(i)];
  return v;
}

std::int64_t checksum_of(std::span<const std::uint8_t> bytes) { return static_cast<std::int64_t>(fnv1a64(bytes)); }

}  // namespace

std::optional<mtg::header_t> peek_header(std::span<const std::uint8_t> message) {
  if (message.size() < 8) return std::nullopt;
  mtg::header_t h{};
  const int len = static_cast<int>(message.size());
  if (h._decodeNoHash(message.data(), 8, len - 8) < 0) return std::nullopt;
  return h;
}

std::vector<std::uint8_t> encode_event_log(const std::vector<LoggedEvent>& events) {
  std::vector<std::uint8_t> out;
  std::int64_t n = 0;
  for (const LoggedEvent& e : events) {
    put_be(out, kSyncWord, 4);
    put_be(out, static_cast<std::uint64_t>(n++), 8);
    put_be(out, static_cast<std::uint64_t>(e.utime), 8);
    put_be(out, e.channel.size(), 4);
    put_be(out, e.data.size(), 4);
    out.insert(out.end(), e.channel.begin(), e.channel.end());
    out.insert(out.end(), e.data.begin(), e.data.end());
  }
  return out;
}

std::vector<LoggedEvent> decode_event_log(std::span<const std::uint8_t> bytes, const std::string& origin) {
  std::vector<LoggedEvent> out;
  std::size_t at = 0;
  while (at < bytes.size()) {
    if (bytes.size() - at < kEventHeaderBytes || get_be(bytes, at, 4) != kSyncWord) {
      throw Error(origin + ": malformed event log at byte " + std::to_string(at));
    }
    LoggedEvent e;
    e.utime = static_cast<std::int64_t>(get_be(bytes, at + 12, 8));
    const std::size_t channel_len = get_be(bytes, at + 20, 4);
    const std::size_t data_len = get_be(bytes, at + 24, 4);
    at += kEventHeaderBytes;
    if (bytes.size() - at < channel_len + data_len) {
      throw Error(origin + ": event log truncated at byte " + std::to_string(at));
    }
    e.channel.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                     bytes.begin() + static_cast<std::ptrdiff_t>(at + channel_len));
    at += channel_len;
    e.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                  bytes.begin() + static_cast<std::ptrdiff_t>(at + data_len));
    at += data_len;
    out.push_back(std::move(e));
  }
  return out;
}

std::vector<mtg::record_chunk_t> make_chunks(const mtg::header_t& header, const std::string& lease_id,
                                             std::span<const std::uint8_t> log, int chunk_bytes) {
  const std::size_t size = static_cast<std::size_t>(std::max(1, chunk_bytes));
  const int count = static_cast<int>(std::max<std::size_t>(1, (log.size() + size - 1) / size));
  const std::int64_t checksum = checksum_of(log);
  std::vector<mtg::record_chunk_t> out;
  for (int i = 0; i < count; ++i) {
    mtg::record_chunk_t c{};
    c.header = header;
    c.lease_id = lease_id;
    c.index = i;
    c.count = count;
    c.total_bytes = static_cast<std::int64_t>(log.size());
    c.checksum = checksum;
    const std::size_t begin = std::min(log.size(), static_cast<std::size_t>(i) * size);
    const std::size_t end = std::min(log.size(), begin + size);
    c.data.assign(log.begin() + static_cast<std::ptrdiff_t>(begin), log.begin() + static_cast<std::ptrdiff_t>(end));
    c.size = static_cast<std::int32_t>(c.data.size());
    out.push_back(std::move(c));
  }
  return out;
}

void ChunkAssembly::add(const mtg::record_chunk_t& c) {
  const std::string what = "recording " + c.lease_id;
  if (c.count <= 0 || c.index < 0 || c.index >= c.count || c.size != static_cast<std::int32_t>(c.data.size())) {
    throw Error(what + ": malformed chunk " + std::to_string(c.index) + "/" + std::to_string(c.count));
  }
  if (count_ < 0) {
    count_ = c.count;
    total_ = c.total_bytes;
    checksum_ = c.checksum;
    parts_.assign(static_cast<std::size_t>(count_), std::nullopt);
  } else if (c.count != count_ || c.total_bytes != total_ || c.checksum != checksum_) {
    throw Error(what + ": chunk " + std::to_string(c.index) + " belongs to another version of the recording");
  }
  auto& part = parts_[static_cast<std::size_t>(c.index)];
  if (part) return;  // a resent chunk
  part = c.data;
  ++received_;
}

bool ChunkAssembly::complete() const { return count_ > 0 && received_ == count_; }

std::vector<std::uint8_t> ChunkAssembly::bytes() const {
  if (!complete()) throw Error("recording incomplete: " + std::to_string(received_) + " of " + std::to_string(count_) + " chunks");
  std::vector<std::uint8_t> out;
  out.reserve(static_cast<std::size_t>(total_));
  for (const auto& part : parts_) out.insert(out.end(), part->begin(), part->end());
  if (static_cast<std::int64_t>(out.size()) != total_ || checksum_of(out) != checksum_) {
    throw Error("recording damaged: " + std::to_string(out.size()) + " bytes (expected " + std::to_string(total_) +
                ") or checksum mismatch");
  }
  return out;
}

}  // namespace mtg::orchestrator::remote
