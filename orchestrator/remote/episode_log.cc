#include "orchestrator/remote/episode_log.h"

#include <algorithm>

#include "core/util/error.h"
#include "core/util/hash.h"

namespace mtg::orchestrator::remote {
namespace {

std::int64_t checksum_of(std::span<const std::uint8_t> bytes) { return static_cast<std::int64_t>(fnv1a64(bytes)); }

}  // namespace

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
