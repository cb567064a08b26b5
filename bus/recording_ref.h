#pragma once
// A recording kept where it was made (docs/multihost.md, "Recordings that stay where they are
// made"): a multi-host run with `--recordings shared:PATH` or `--recordings worker` does not send
// each attempt's recording to the coordinator; the worker writes it to a file and only this
// reference, with the file's size and SHA-256, crosses the bus. The coordinator stores the
// reference in results.sqlite (table `recordings`), in the same transaction as the attempt's
// verdict, so the two never disagree; readers (bus/recording.h) read the files it names in
// episode order, as they read a merged recording, and name a file that is missing or whose
// bytes are not the ones referenced.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bus/episode_id.h"
#include "core/util/sha256.h"
#include "core/store/sqlite.h"
#include "mtg/recording_ref_t.hpp"

namespace mtg::bus {

struct RecordingRef {
  EpisodeId episode;
  int attempt = 0;
  /// The file: relative to the run folder when it lies inside it (the folder can move), else
  /// absolute, as on the host that wrote it.
  std::string location;
  std::string host;     // the host that wrote it
  bool shared = false;  // in a folder every host sees (else kept on `host` until `mtg gather`)
  std::int64_t bytes = 0;
  std::string sha256;   // 64 lower-case hex digits
};

using mtg::sha256_hex;  // core/util/sha256.h

/// An attempt's recording is named "E<id>-a<attempt>.lcmlog", in the run folder's episodes/, a
/// worker's <dir>/<run id>/episodes/ or the shared folder's <run id>/: a reference to any other
/// name is refused (issue 55: a key holder once made the coordinator keep /etc/passwd).
std::string recording_file_name(EpisodeId episode, int attempt);
/// The most bytes one attempt's recording may have (a rendered 15-step episode is a few MiB).
inline constexpr std::int64_t kMaxRecordingBytes = std::int64_t{1} << 30;

/// "" when `file` may hold the recording `ref` names: named recording_file_name(ref.episode,
/// ref.attempt), not a link (its name, not what a link names), a regular file, and a stored size
/// between 1 byte and kMaxRecordingBytes; else why not, in words.
std::string recording_misfit(const std::filesystem::path& file, const RecordingRef& ref);

/// The reference to the recording `bytes` of an attempt, kept at `location` on `host`.
RecordingRef reference_to(EpisodeId episode, int attempt, std::string location, std::string host, bool shared,
                          std::span<const std::uint8_t> bytes);

/// The message for `ref` (header left to the caller) and back; from_message keeps the absolute
/// location the worker sent.
mtg::recording_ref_t to_message(const RecordingRef& ref);
RecordingRef from_message(const mtg::recording_ref_t& m);

/// `ref` with its location relative to `run_dir` where the file lies inside it.
RecordingRef relative_to(RecordingRef ref, const std::filesystem::path& run_dir);
/// Where the file of `ref` is read from, for a run in `run_dir`.
std::filesystem::path resolve(const RecordingRef& ref, const std::filesystem::path& run_dir);

/// Creates the `recordings` table if it is missing.
void create_recording_refs(store::Database& db);
/// Keeps `ref` as its episode's recording (replacing an earlier one of the episode).
void store_recording_ref(store::Database& db, const RecordingRef& ref);
/// The references of results.sqlite `results_file`, by episode id; none when it has no table or
/// does not exist. @throws mtg::Error naming the file when it cannot be read.
std::vector<RecordingRef> read_recording_refs(const std::filesystem::path& results_file);

/// "" when `file` is the recording `ref` names (its size and SHA-256); otherwise one line saying
/// what is wrong: missing (and where it is kept), cut short or grown, or other bytes.
std::string check_recording(const std::filesystem::path& file, const RecordingRef& ref);

}  // namespace mtg::bus
