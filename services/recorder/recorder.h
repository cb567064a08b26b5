#pragma once
// The run's recording: every message of the run on the bus, appended to an LCM event log that
// lcm-logplayer replays and lcm::LogFile reads. It does what lcm-logger does, and three things
// lcm-logger does not (docs/runtime.md, "Recording"):
//   - its subscription queue holds kQueueCapacity messages (lcm-logger 1.3.1 keeps LCM's default
//     of 30 and silently lost a quarter of a 16-episode run's messages on 2 busy cores);
//   - a restarted recorder first cuts a torn last event (its predecessor killed mid-write) off the
//     file, and a recorder that cannot write (a full disk) cuts what it could not finish off
//     before it stops, so the log stays readable to its end by every tool;
//   - once an episode's result is written and flushed it says so (recorded_t on MTG_RECORDED):
//     the orchestrator stores a result only then, and re-runs the attempts it never heard of.
// With a run id it keeps the messages of that run (and those of no run), nothing else, and
// acknowledges that run's results; without one it records the whole bus and acknowledges none.

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "bus/bus.h"
#include "bus/header.h"

namespace mtg::services {

class Recorder {
 public:
  /// Subscribes to every channel of `bus`, then opens `path` for appending (creating it), so a
  /// file that exists means the recording is live. A torn last event is cut off first.
  /// @throws mtg::Error naming the file when it cannot be opened or repaired.
  Recorder(bus::Bus& bus, bus::HeaderStamper& stamp, const std::filesystem::path& path, std::string run_id = "");

  void flush();
  std::int64_t events() const { return events_; }
  const std::filesystem::path& path() const { return path_; }
  /// Bytes cut off a torn last event when the file was opened (0 when it was whole).
  std::uintmax_t repaired_bytes() const { return repaired_; }

 private:
  void write(const std::string& channel, std::span<const std::uint8_t> data, std::int64_t recv_utime);
  /// After a failed write: drops what is buffered, cuts the file back to the end of the last
  /// flush (whole events only) and throws, naming the file and what was cut.
  [[noreturn]] void fail(const std::string& why);

  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  std::filesystem::path path_;
  std::string run_id_;
  std::uintmax_t repaired_ = 0;
  lcm::LogFile log_;
  std::int64_t events_ = 0;
  long flushed_to_ = 0;  // file length after the last successful flush: whole events only
};

}  // namespace mtg::services
