#include "bus/recording.h"

#include <algorithm>
#include <vector>

#include "bus/header.h"
#include "core/util/error.h"

namespace mtg::bus {

void for_each_recorded_event(const std::filesystem::path& run_dir,
                             const std::function<void(const lcm::LogEvent&)>& fn) {
  if (!std::filesystem::is_directory(run_dir)) throw Error(run_dir.string() + ": no run folder");
  std::vector<std::filesystem::path> logs;
  for (const auto& entry : std::filesystem::directory_iterator(run_dir)) {
    if (entry.path().extension() == ".lcmlog") logs.push_back(entry.path());
  }
  std::sort(logs.begin(), logs.end());
  if (logs.empty()) throw Error(run_dir.string() + ": no recording (*.lcmlog)");
  for (const auto& log : logs) {
    lcm::LogFile file(log.string(), "r");
    if (!file.good()) throw Error(log.string() + ": cannot read the recording");
    for (const lcm::LogEvent* ev = file.readNextEvent(); ev != nullptr; ev = file.readNextEvent()) {
      // A recording of another schema would be read wrongly without a word: refuse it.
      if (ev->channel.starts_with("MTG_")) {
        const auto header = peek_header({static_cast<const std::uint8_t*>(ev->data), static_cast<std::size_t>(ev->datalen)});
        if (header && !speaks_our_schema(*header)) {
          throw Error(log.string() + ": " + schema_mismatch(*header, "the message on " + ev->channel) +
                      " (read it with the mtg that recorded it)");
        }
      }
      fn(*ev);
    }
  }
}

}  // namespace mtg::bus
