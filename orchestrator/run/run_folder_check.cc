#include "orchestrator/run/run_folder_check.h"

#include <array>
#include <string>

#include "core/util/atomic_file.h"
#include "core/util/error.h"

namespace mtg::orchestrator {

namespace fs = std::filesystem;

namespace {

// What a run folder holds (docs/runtime.md, "The run folder"), and the journals beside its databases.
constexpr std::array kFiles = {".lock",          "plan.json",        "sessions.jsonl",   "results.sqlite",
                               "marks.sqlite",   "leases.sqlite",    "rejudge.sqlite",   "report.html",
                               "report.png",     "report.json",      "card.md",          "card.json",
                               "bus.json",       "bus.key",          "suite.json",       "bus-merged.lcmlog"};
constexpr std::array kDatabases = {"results.sqlite", "marks.sqlite", "leases.sqlite", "rejudge.sqlite"};
constexpr std::array kFolders = {"logs", "episodes", "slurm", "replay"};

void require_folder(const fs::path& folder) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(folder, ec);
  if (ec || !fs::exists(st) || fs::is_directory(st)) return;
  throw Error(folder.string() + (fs::is_symlink(st) ? ": is a symbolic link" : ": is not a folder") +
              "; the run writes into it: remove it, or give another --out");
}

}  // namespace

void check_run_folder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return;
  for (const char* name : kFiles) require_plain_file(dir / name);
  for (const char* name : kDatabases) {
    for (const char* suffix : {"-journal", "-wal", "-shm"}) require_plain_file(dir / (std::string(name) + suffix));
  }
  for (const char* name : kFolders) require_folder(dir / name);
  // Recordings (bus-<k>.lcmlog) and every process's log: each appended to in place.
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("bus-", 0) == 0 && e.path().extension() == ".lcmlog") require_plain_file(e.path());
  }
  for (const char* sub : {"logs", "episodes"}) {
    if (!fs::is_directory(dir / sub, ec)) continue;
    for (const auto& e : fs::directory_iterator(dir / sub, ec)) require_plain_file(e.path());
  }
}

}  // namespace mtg::orchestrator
