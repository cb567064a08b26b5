#pragma once
// One writer per run folder (docs/runtime.md, "One run per folder"). Two `mtg run` (or `mtg play`)
// on the same --out would split its episodes and interleave its recording into garbage, so the
// run holds an exclusive lock on `<run>/.lock` while it lasts. The lock is the kernel's (flock):
// a run that is killed, however, releases it with its last file descriptor, so a stale lock never
// blocks a resume. The file keeps who holds it, for the refusal's one line.

#include <filesystem>
#include <string>

namespace mtg::orchestrator {

class RunLock {
 public:
  /// Takes the folder's lock (making the folder and its lock file if need be).
  /// @throws mtg::Error "<dir> is in use by process <pid> on <host> ..." when another holds it.
  explicit RunLock(const std::filesystem::path& dir, const std::string& what = "mtg run");
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  int fd_ = -1;
};

/// Whether a run (or play) holds `dir`'s lock now: a reader's question (the viewer's), which
/// neither makes nor takes the lock. False for a folder without a lock file.
bool run_in_progress(const std::filesystem::path& dir);

}  // namespace mtg::orchestrator
