#include "orchestrator/remote/merge_recordings.h"

#include <fstream>
#include <iterator>
#include <vector>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "orchestrator/remote/episode_log.h"
#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator::remote {

namespace fs = std::filesystem;

fs::path episode_log_path(const fs::path& run_dir, bus::EpisodeId episode_id, int attempt) {
  return run_dir / "episodes" / ("E" + to_string(episode_id) + "-a" + std::to_string(attempt) + ".lcmlog");
}

std::int64_t merge_recordings(const fs::path& run_dir) {
  std::vector<LoggedEvent> merged;
  for (const EpisodeRow& row : read_results(run_dir / "results.sqlite")) {
    const fs::path file = episode_log_path(run_dir, row.episode_id, row.attempt);
    if (!fs::exists(file)) continue;  // given up without a recording
    std::ifstream in(file, std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
    if (!in.good() && !in.eof()) throw Error(file.string() + ": cannot read the episode recording");
    auto events = decode_event_log(bytes, file.string());
    merged.insert(merged.end(), std::make_move_iterator(events.begin()), std::make_move_iterator(events.end()));
  }
  // Built as bus-merged.lcmlog.partial, which readers of *.lcmlog never pick up half written.
  const auto bytes = encode_event_log(merged);
  write_file_atomically(run_dir / "bus-merged.lcmlog", [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
  return static_cast<std::int64_t>(merged.size());
}

}  // namespace mtg::orchestrator::remote
