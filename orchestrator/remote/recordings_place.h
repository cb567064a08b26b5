#pragma once
// Where a multi-host run's recordings go (`mtg run --remote --recordings ...`, docs/multihost.md
// "Recordings that stay where they are made"): a vocabulary of three, parsed once at the command
// line and carried by name in the run's announcement (run_info_t.recordings) and plan.json.

#include <filesystem>
#include <string>

namespace mtg::orchestrator::remote {

struct RecordingsPlace {
  enum class Kind {
    kCoordinator,  // each attempt's recording goes to the coordinator in chunks (the default)
    kShared,       // workers write them into `folder`/<run id>/, a folder every host sees
    kWorker,       // kept in each worker's own folder; `mtg gather` brings them in later
  };
  Kind kind = Kind::kCoordinator;
  std::filesystem::path folder;  // kShared: absolute

  /// "coordinator", "shared:<folder>", "worker".
  std::string to_string() const;
  /// The folder of one run's recordings (kShared).
  std::filesystem::path run_folder(const std::string& run_id) const { return folder / run_id; }
  bool operator==(const RecordingsPlace&) const = default;
};

/// @throws mtg::Error naming the value and the three forms it may take ("" = coordinator).
RecordingsPlace parse_recordings_place(const std::string& text);

/// The file a coordinator leaves in a shared folder (run_folder) with its session token: a worker
/// that cannot read it there is not on the same file system and stays out of the run.
inline constexpr const char* kSharedProbe = "shared.probe";

}  // namespace mtg::orchestrator::remote
