#pragma once
// Reading a run's recording: every `*.lcmlog` of the run folder (one per `mtg run` invocation),
// in name order, as LCM log events. Replay, re-judging and the runtime bench all read it so.

#include <lcm/lcm-cpp.hpp>

#include <filesystem>
#include <functional>

namespace mtg::bus {

/// Calls `fn(event)` for every event of every recording in `run_dir`, file by file in name order.
/// @throws mtg::Error naming the folder when it holds no recording, or the file it cannot read.
void for_each_recorded_event(const std::filesystem::path& run_dir,
                             const std::function<void(const lcm::LogEvent&)>& fn);

}  // namespace mtg::bus
