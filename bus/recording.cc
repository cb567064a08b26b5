#include "bus/recording.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <vector>

#include "bus/header.h"
#include "core/util/error.h"

namespace mtg::bus {

namespace {

// An event's bytes in an LCM log: sync word, event number, timestamp, two lengths, channel, data.
std::int64_t event_bytes(const lcm::LogEvent& ev) {
  return 4 + 8 + 8 + 4 + 4 + static_cast<std::int64_t>(ev.channel.size()) + ev.datalen;
}

// The offset of the first LCM sync word (0xEDA1DA01, big-endian) at or after `from`, or -1.
std::int64_t next_sync_word(const std::filesystem::path& log, std::int64_t from) {
  std::ifstream in(log, std::ios::binary);
  in.seekg(from);
  std::uint32_t window = 0;
  std::int64_t pos = from;
  for (int c = in.get(); c != EOF; c = in.get(), ++pos) {
    window = (window << 8) | static_cast<std::uint32_t>(c);
    if (pos - from >= 3 && window == 0xEDA1DA01u) return pos - 3;
  }
  return -1;
}

}  // namespace

std::string describe(const RecordingDamage& d) {
  if (!d.problem.empty()) return d.problem;
  const std::string where = " at byte " + std::to_string(d.offset) + " of " + std::to_string(d.offset + d.bytes);
  if (d.at_end) {
    return d.file.filename().string() + ": its last " + std::to_string(d.bytes) + " bytes" + where +
           " are not a whole event (torn when a recorder stopped while writing, or damaged); not read";
  }
  return d.file.filename().string() + ": " + std::to_string(d.bytes) + " unreadable bytes at byte " +
         std::to_string(d.offset) + " (skipped; the recording is damaged there)";
}

std::string damage_for(const std::vector<RecordingDamage>& damage, EpisodeId episode) {
  std::vector<std::string> lines;
  for (const RecordingDamage& d : damage) {
    if (d.episode && *d.episode == episode) return describe(d);  // its own file: the reason
  }
  for (const RecordingDamage& d : damage) {
    if (!d.episode) lines.push_back(describe(d));
  }
  if (lines.empty()) return "";
  return lines.front() + (lines.size() > 1 ? "; and " + std::to_string(lines.size() - 1) + " more" : "");
}

RecordingRead read_recording(const std::filesystem::path& log, std::int64_t from,
                             const std::function<void(const lcm::LogEvent&, std::int64_t offset)>& fn) {
  lcm::LogFile file(log.string(), "r");
  if (!file.good()) throw Error(log.string() + ": cannot read the recording");
  std::FILE* f = file.getFilePtr();
  const auto size = static_cast<std::int64_t>(std::filesystem::file_size(log));
  RecordingRead read;
  std::int64_t at = from;  // where the next event should start
  if (from > 0 && std::fseek(f, static_cast<long>(from), SEEK_SET) != 0) {
    throw Error(log.string() + ": cannot seek in the recording");
  }
  while (true) {
    for (const lcm::LogEvent* ev = file.readNextEvent(); ev != nullptr; ev = file.readNextEvent()) {
      const std::int64_t end = std::ftell(f);
      const std::int64_t start = end - event_bytes(*ev);
      if (start > at) read.damage.push_back({log, at, start - at, false, "", std::nullopt});
      at = end;
      fn(*ev, start);
    }
    if (at >= size) break;
    // LCM stops at an event whose header does not hold; the events after it are still whole:
    // go on from the next sync word.
    const std::int64_t next = next_sync_word(log, at + 1);
    if (next < 0) {
      read.damage.push_back({log, at, size - at, true, "", std::nullopt});
      break;
    }
    read.damage.push_back({log, at, next - at, false, "", std::nullopt});
    at = next;
    if (std::fseek(f, static_cast<long>(next), SEEK_SET) != 0) throw Error(log.string() + ": cannot seek in the recording");
  }
  read.end = at;
  return read;
}

std::vector<RecordingFile> recording_files(const std::filesystem::path& run_dir) {
  std::vector<RecordingFile> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(run_dir, ec)) {
    if (entry.path().extension() == ".lcmlog") out.push_back({entry.path(), std::nullopt});
  }
  std::sort(out.begin(), out.end(), [](const RecordingFile& a, const RecordingFile& b) { return a.path < b.path; });
  const bool merged = std::any_of(out.begin(), out.end(),
                                  [](const RecordingFile& f) { return f.path.filename() == "bus-merged.lcmlog"; });
  if (merged) return out;
  for (RecordingRef& ref : read_recording_refs(run_dir / "results.sqlite")) {
    const std::filesystem::path file = resolve(ref, run_dir);
    out.push_back({file, std::move(ref)});
  }
  return out;
}

std::vector<RecordingDamage> for_each_recorded_event(const std::filesystem::path& run_dir,
                                                     const std::function<void(const lcm::LogEvent&)>& fn) {
  if (!std::filesystem::is_directory(run_dir)) throw Error(run_dir.string() + ": no run folder");
  const std::vector<RecordingFile> files = recording_files(run_dir);
  if (files.empty()) throw Error(run_dir.string() + ": no recording (*.lcmlog, or recordings referenced by results.sqlite)");
  std::vector<RecordingDamage> damage;
  for (const RecordingFile& file : files) {
    const auto& log = file.path;
    if (file.ref) {
      std::string problem = check_recording(log, *file.ref);
      if (!problem.empty()) {
        damage.push_back({log, 0, file.ref->bytes, false, std::move(problem), file.ref->episode});
        continue;
      }
    }
    auto read = read_recording(log, 0, [&](const lcm::LogEvent& ev, std::int64_t) {
      // A recording of another schema would be read wrongly without a word: refuse it.
      if (ev.channel.starts_with("MTG_")) {
        const auto header = peek_header({static_cast<const std::uint8_t*>(ev.data), static_cast<std::size_t>(ev.datalen)});
        if (header && !speaks_our_schema(*header)) {
          throw Error(log.string() + ": " + schema_mismatch(*header, "the message on " + ev.channel) +
                      " (read it with the mtg that recorded it)");
        }
      }
      fn(ev);
    });
    damage.insert(damage.end(), read.damage.begin(), read.damage.end());
  }
  return damage;
}

}  // namespace mtg::bus
