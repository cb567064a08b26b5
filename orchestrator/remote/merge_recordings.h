#pragma once
// The run folder's recording of a multi-host run. Each stored attempt's recording arrives from
// its worker as episodes/E<id>-a<attempt>.lcmlog (that host's bus, in the order it saw them);
// merging writes bus-merged.lcmlog with the attempts whose results are in results.sqlite, by
// episode id, each in its host's order -- by episode and sequence, never by the hosts' clocks,
// which need not agree. Replay, rejudge and `mtg images` read it like a one-host recording.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "bus/episode_id.h"

namespace mtg::orchestrator::remote {

/// Where an attempt's recording is kept in the run folder.
std::filesystem::path episode_log_path(const std::filesystem::path& run_dir, bus::EpisodeId episode_id, int attempt);
/// Writes an attempt's recording there, whole or not at all; returns the file.
/// @throws mtg::Error naming the file when it cannot be written.
std::filesystem::path store_episode_log(const std::filesystem::path& run_dir, bus::EpisodeId episode_id, int attempt,
                                        std::span<const std::uint8_t> bytes);

/// Rewrites <run_dir>/bus-merged.lcmlog; returns the number of events written.
/// @throws mtg::Error naming the file it cannot read or write.
std::int64_t merge_recordings(const std::filesystem::path& run_dir);

}  // namespace mtg::orchestrator::remote
