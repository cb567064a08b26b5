#include "orchestrator/remote/merge_recordings.h"

#include <iterator>
#include <vector>

#include "bus/recording_ref.h"
#include "core/util/file_bytes.h"
#include "core/util/error.h"
#include "orchestrator/remote/episode_log.h"
#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator::remote {

namespace fs = std::filesystem;

fs::path episode_log_path(const fs::path& run_dir, bus::EpisodeId episode_id, int attempt) {
  return run_dir / "episodes" / bus::recording_file_name(episode_id, attempt);
}

fs::path store_episode_log(const fs::path& run_dir, bus::EpisodeId episode_id, int attempt,
                           std::span<const std::uint8_t> bytes) {
  const fs::path file = episode_log_path(run_dir, episode_id, attempt);
  write_file_bytes_atomically(file, bytes);
  return file;
}

std::int64_t merge_recordings(const fs::path& run_dir) {
  std::vector<LoggedEvent> merged;
  for (const EpisodeRow& row : read_results(run_dir / "results.sqlite")) {
    const fs::path file = episode_log_path(run_dir, row.episode_id, row.attempt);
    if (!fs::exists(file)) continue;  // given up without a recording
    auto events = decode_event_log(read_file_bytes(file), file.string());
    merged.insert(merged.end(), std::make_move_iterator(events.begin()), std::make_move_iterator(events.end()));
  }
  // Built as bus-merged.lcmlog.partial, which readers of *.lcmlog never pick up half written.
  write_file_bytes_atomically(run_dir / "bus-merged.lcmlog", encode_event_log(merged));
  return static_cast<std::int64_t>(merged.size());
}

}  // namespace mtg::orchestrator::remote
