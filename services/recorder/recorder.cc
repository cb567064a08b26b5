#include "services/recorder/recorder.h"

#include <cstdio>

#include "core/util/error.h"

namespace mtg::services {

Recorder::Recorder(bus::Bus& bus, const std::filesystem::path& path) : path_(path), log_(path.string(), "a") {
  if (!log_.good()) throw Error(path_.string() + ": cannot open the recording for writing");
  bus.subscribe_raw(".*", [this](const std::string& channel, std::span<const std::uint8_t> data, std::int64_t utime) {
    write(channel, data, utime);
  });
}

void Recorder::write(const std::string& channel, std::span<const std::uint8_t> data, std::int64_t recv_utime) {
  lcm::LogEvent ev;
  ev.eventnum = events_;
  ev.timestamp = recv_utime;  // lcm-logplayer paces the replay by these
  ev.channel = channel;
  ev.datalen = static_cast<int32_t>(data.size());
  ev.data = const_cast<std::uint8_t*>(data.data());  // LogFile only reads it
  if (log_.writeEvent(&ev) != 0) throw Error(path_.string() + ": cannot write to the recording (disk full?)");
  ++events_;
}

void Recorder::flush() { std::fflush(log_.getFilePtr()); }

}  // namespace mtg::services
