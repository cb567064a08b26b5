#pragma once
// Writing a file so that readers never see half of it: the content goes to a partial file next
// to it, renamed over it once complete. An interrupted writer leaves the old file (or none).
//
// Each writer builds its own partial, `<file>.partial-<host>-<pid>`, so two writers of one file
// (two runs given the same output) never write into each other's: both finish, and the last
// rename wins. A partial of this host whose process is gone was left by a killed writer; a
// writer of a long-lived file (the task database) removes such partials of its file first, with
// their SQLite journals. Quick writes do not look: their folder may hold thousands of files
// (episode logs, images), and a writer is rarely killed inside one.

#include <filesystem>
#include <functional>
#include <ostream>

namespace mtg {

/// Throws mtg::Error naming `target` when it exists and is not a regular file (a device, a FIFO,
/// a folder): a writer that renames over it would replace it.
void require_replaceable(const std::filesystem::path& target);

/// Throws mtg::Error naming `target` when the name is a symbolic link (a writer that opens it
/// would write through it, wherever it points: a planted link in a shared folder) or exists and is
/// not a regular file. For outputs written in place (locks, appended logs, databases), which no
/// rename can protect.
void require_plain_file(const std::filesystem::path& target);

/// Opens `file` for writing in place (`flags`: O_WRONLY or O_RDWR, with O_CREAT, O_APPEND as
/// needed) without following a link at its name, and only if it is a regular file; close-on-exec.
/// @throws mtg::Error naming the file.
int open_plain_file(const std::filesystem::path& file, int flags, unsigned mode = 0644);

/// Calls `write(stream)` on a binary stream to a partial file, then renames it to `file`.
/// @throws mtg::Error naming `file` when it cannot be written.
void write_file_atomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& write);

/// The partial file of one writer of `target`: created (empty) with the writer, renamed over the
/// target by commit(), removed if it goes uncommitted.
class PartialFile {
 public:
  enum class Stale { kLeave, kRemove };
  /// With Stale::kRemove, removes the partials of `target` that killed writers left first.
  /// @throws mtg::Error naming `target` if the partial cannot be created (this process writes
  /// `target` already, or its folder is not writable).
  explicit PartialFile(std::filesystem::path target, Stale stale = Stale::kLeave);
  ~PartialFile();
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// Renames the partial over the target. @throws mtg::Error naming the target if it cannot.
  void commit();

 private:
  std::filesystem::path target_, path_;
  bool committed_ = false;
};

}  // namespace mtg
