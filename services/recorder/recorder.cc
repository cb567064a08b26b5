#include "services/recorder/recorder.h"

#include <stdio_ext.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "bus/channels.h"
#include "bus/event_log.h"
#include "bus/header.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "mtg/recorded_t.hpp"

namespace mtg::services {
namespace {

// Cuts a torn last event off `path` (a killed writer's), before anything is appended to it;
// returns the bytes removed.
std::uintmax_t repair(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return 0;
  const std::uintmax_t size = std::filesystem::file_size(path);
  const std::uintmax_t whole = bus::whole_events_length(path);
  if (whole == size) return 0;
  std::filesystem::resize_file(path, whole, ec);
  if (ec) throw Error(path.string() + ": cannot cut its torn last event off (" + ec.message() + ")");
  return size - whole;
}

}  // namespace

Recorder::Recorder(bus::Bus& bus, bus::HeaderStamper& stamp, const std::filesystem::path& path, std::string run_id)
    : bus_(bus), stamp_(stamp), path_(path), run_id_(std::move(run_id)), repaired_((require_plain_file(path), repair(path))),
      log_(path.string(), "a") {
  if (!log_.good()) throw Error(path_.string() + ": cannot open the recording for writing");
  // A bigger buffer than stdio's 4 KiB: an observation alone filled that, so nearly every message
  // cost a write(2). What is on disk is unchanged: every result and every 100 ms still flush.
  std::setvbuf(log_.getFilePtr(), nullptr, _IOFBF, std::size_t{1} << 20);
  std::fseek(log_.getFilePtr(), 0, SEEK_END);
  flushed_to_ = std::ftell(log_.getFilePtr());
  bus.subscribe_raw(".*", [this](const std::string& channel, std::span<const std::uint8_t> data, std::int64_t utime) {
    write(channel, data, utime);
  });
}

void Recorder::write(const std::string& channel, std::span<const std::uint8_t> data, std::int64_t recv_utime) {
  const auto header = bus::peek_header(data);
  if (!run_id_.empty() && (!header || (!header->run_id.empty() && header->run_id != run_id_))) return;
  lcm::LogEvent ev;
  ev.eventnum = events_;
  ev.timestamp = recv_utime;  // lcm-logplayer paces the replay by these
  ev.channel = channel;
  ev.datalen = static_cast<int32_t>(data.size());
  ev.data = const_cast<std::uint8_t*>(data.data());  // LogFile only reads it
  if (log_.writeEvent(&ev) != 0) fail(std::strerror(errno));
  ++events_;
  if (!run_id_.empty() && channel == bus::kEpisodeResult && header && header->episode_id >= 0) {
    // The result is the attempt's last message: once it is on disk, the whole attempt is.
    flush();
    mtg::recorded_t ack{};
    ack.header = stamp_.next(bus::episode_of(*header), header->attempt, "recorded");
    ack.header.run_id = header->run_id;
    ack.file = path_.string();
    ack.events = events_;
    bus_.publish(bus::kRecorded, ack);
    stamp_.forget_episode(bus::episode_of(*header));  // one acknowledgement per result
  }
}

void Recorder::flush() {
  // With a large buffer most write errors surface here: a result must never be acknowledged
  // before its bytes are on disk.
  if (std::fflush(log_.getFilePtr()) != 0) fail(std::strerror(errno));
  flushed_to_ = std::ftell(log_.getFilePtr());
}

void Recorder::fail(const std::string& why) {
  // What stdio still holds would go out when the file closes, torn by the same error: dropped.
  // Those events were never acknowledged, so their attempts run again.
  std::FILE* fp = log_.getFilePtr();
  __fpurge(fp);
  std::string cut = "the file ends after the last whole event";
  const off_t length = ::lseek(::fileno(fp), 0, SEEK_END);
  if (length > flushed_to_) {
    cut = ::ftruncate(::fileno(fp), flushed_to_) == 0
              ? "cut the " + std::to_string(length - flushed_to_) + " bytes of unfinished events off"
              : "could not cut the unfinished events off (" + std::string(std::strerror(errno)) + ")";
  }
  throw Error(path_.string() + ": cannot write to the recording (" + why + "; disk full?); " + cut +
              ", so it is whole up to byte " + std::to_string(flushed_to_));
}

}  // namespace mtg::services
