#pragma once
// LCM's event-log format (lcm/eventlog.c), the bytes of a recording: every event is a sync word,
// its number, receive time, channel length and data length (big-endian), then the channel and
// the message. Recordings are written by the recorder, shipped between hosts in chunks, merged,
// and read back by the stock tools; this is the one reading and writing of the format.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace mtg::bus {

struct LoggedEvent {
  std::string channel;
  std::int64_t utime = 0;  // receive time (lcm-logplayer paces by it)
  std::vector<std::uint8_t> data;
};

/// The events in LCM's event-log format, numbered from 0.
std::vector<std::uint8_t> encode_event_log(const std::vector<LoggedEvent>& events);
/// @throws mtg::Error naming `origin` on a truncated or malformed log.
std::vector<LoggedEvent> decode_event_log(std::span<const std::uint8_t> bytes, const std::string& origin);

/// How many bytes at the start of `file` are whole events: where a writer killed in the middle
/// of an event stopped being readable. The file's size when it is whole.
/// @throws mtg::Error naming the file when it cannot be read.
std::uintmax_t whole_events_length(const std::filesystem::path& file);

}  // namespace mtg::bus
