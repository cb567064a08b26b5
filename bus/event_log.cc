#include "bus/event_log.h"

#include <cstdio>
#include <memory>

#include "core/util/error.h"

namespace mtg::bus {
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

}  // namespace

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

std::uintmax_t whole_events_length(const std::filesystem::path& file) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(file.c_str(), "rb"), &std::fclose);
  if (!f) throw Error(file.string() + ": cannot read the recording");
  const std::uintmax_t size = std::filesystem::file_size(file);
  std::uintmax_t whole = 0;
  std::uint8_t head[kEventHeaderBytes];
  while (size - whole >= kEventHeaderBytes && std::fread(head, 1, kEventHeaderBytes, f.get()) == kEventHeaderBytes) {
    const std::span<const std::uint8_t> h(head, kEventHeaderBytes);
    if (get_be(h, 0, 4) != kSyncWord) break;
    const std::uintmax_t body = get_be(h, 20, 4) + get_be(h, 24, 4);
    if (size - whole - kEventHeaderBytes < body) break;  // cut short
    whole += kEventHeaderBytes + body;
    if (std::fseek(f.get(), static_cast<long>(whole), SEEK_SET) != 0) break;
  }
  return whole;
}

}  // namespace mtg::bus
