#pragma once
// Reading a run's recording: every `*.lcmlog` of the run folder (one per `mtg run` invocation),
// in name order, as LCM log events; for a multi-host run whose recordings stayed where they were
// made (bus/recording_ref.h), the files results.sqlite references, in episode order, each checked
// against its size and SHA-256 first. Replay, re-judging, the viewer and the benches read it so.
//
// LCM's reader says nothing about damage: it skips bytes until the next sync word, and where an
// event's header does not hold it drops the event before it too and stops as if the file had
// ended. Readers here compare where each event ends with where it should, go on from the next
// sync word after a stop, and name each unreadable stretch with the byte where it starts.

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bus/recording_ref.h"

namespace mtg::bus {

/// Bytes of a recording that could not be read as events.
struct RecordingDamage {
  std::filesystem::path file;
  std::int64_t offset = 0;  // where the unreadable bytes start
  std::int64_t bytes = 0;   // how many were skipped (to the next event or the end)
  bool at_end = false;      // a torn last event (a recorder stopped mid-write), not damage inside
  /// A referenced recording that is missing or not the one referenced (check_recording's line);
  /// none of it was read.
  std::string problem;
  /// The episode a referenced recording is of (none for damage inside a run's own logs, which
  /// may hold any episode).
  std::optional<EpisodeId> episode;
};

/// The damage that may explain what the recording lacks of `episode`, as one line ("" when none
/// may): that episode's own referenced file, else damage inside a log; another episode's missing
/// file never.
std::string damage_for(const std::vector<RecordingDamage>& damage, EpisodeId episode);

/// One line: "bus-0.lcmlog: 120 unreadable bytes at byte 4096 of 8192 (skipped)".
std::string describe(const RecordingDamage& damage);

/// What read_recording() found in one file.
struct RecordingRead {
  std::int64_t end = 0;  // where the last whole event read ends (a torn tail starts there)
  std::vector<RecordingDamage> damage;
};

/// Calls `fn(event, offset)` for every whole event of the recording `log` from byte `from` (an
/// event's start) on, going past damage from the next sync word; a torn tail is reported
/// (at_end) and not read. A live recording's tail may be an event still being written: read
/// again from `end` later. @throws mtg::Error naming the file when it cannot be read.
RecordingRead read_recording(const std::filesystem::path& log, std::int64_t from,
                             const std::function<void(const lcm::LogEvent&, std::int64_t offset)>& fn);

/// One file of a run's recording, in the order it is read.
struct RecordingFile {
  std::filesystem::path path;
  std::optional<RecordingRef> ref;  // a referenced recording (checked before it is read)
};

/// The files of the recording of `run_dir`: its `*.lcmlog` in name order; then, unless one of them
/// is bus-merged.lcmlog, the recordings results.sqlite references, in episode order.
/// @throws mtg::Error naming results.sqlite when it cannot be read.
std::vector<RecordingFile> recording_files(const std::filesystem::path& run_dir);

/// Calls `fn(event)` for every event of every recording in `run_dir`, file by file in name order,
/// and returns what could not be read (a referenced recording that is missing or damaged is not
/// read, and named). @throws mtg::Error naming the folder when it holds no recording, or the file
/// it cannot read.
std::vector<RecordingDamage> for_each_recorded_event(const std::filesystem::path& run_dir,
                                                     const std::function<void(const lcm::LogEvent&)>& fn);

}  // namespace mtg::bus
