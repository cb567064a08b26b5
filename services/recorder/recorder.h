#pragma once
// The run's recording: every message on the bus, appended to an LCM event log that
// lcm-logplayer replays and lcm::LogFile reads. It does what lcm-logger does, with one
// difference that matters on a loaded machine: its subscription queue holds kQueueCapacity
// messages. lcm-logger 1.3.1 keeps LCM's default of 30 and silently lost a quarter of a
// 16-episode run's messages on 2 busy cores (docs/runtime.md, "Recording").

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "bus/bus.h"

namespace mtg::services {

class Recorder {
 public:
  /// Subscribes to every channel of `bus`, then opens `path` for appending (creating it), so a
  /// file that exists means the recording is live. Appending lets a restarted recorder continue.
  /// @throws mtg::Error naming the file when it cannot be opened.
  Recorder(bus::Bus& bus, const std::filesystem::path& path);

  void flush();
  std::int64_t events() const { return events_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  void write(const std::string& channel, std::span<const std::uint8_t> data, std::int64_t recv_utime);

  std::filesystem::path path_;
  lcm::LogFile log_;
  std::int64_t events_ = 0;
};

}  // namespace mtg::services
