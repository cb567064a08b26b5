#pragma once
// Content hashes of dataset files remembered between commands (issue 56: hashing the dataset byte
// by byte was 8.5 % of a Levels 1+2 run, done again by every command). A hash is taken from the
// cache only while the file's device, inode, size, modification and change times are all those
// it was hashed with; the change time cannot be set back by anyone, so a file rewritten to the
// same size with its old modification time is read again. A file changed less than `settle` before
// it was hashed is not remembered (two writes within one tick of the clock would show one time).
// The digest is therefore exactly the one reading every file would give.
//
// The cache is a SQLite file: $MTG_CACHE_DIR/file-hashes.sqlite, else $XDG_CACHE_HOME/mtg/, else
// ~/.cache/mtg/; MTG_CACHE_DIR=off turns it off. Anything wrong with it (unwritable, damaged, a
// link planted at its name) turns it off for the process with a debug line: a command never fails
// nor reads a wrong hash because of its cache. It keeps at most kMaxEntries files.

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace mtg::store {
class Database;
}

namespace mtg::scene {

/// What identifies one version of a file without reading it.
struct FileStamp {
  std::uint64_t device = 0;
  std::uint64_t inode = 0;
  std::int64_t size = 0;
  std::int64_t modified_ns = 0;
  std::int64_t changed_ns = 0;

  bool operator==(const FileStamp&) const = default;
  /// nullopt when it is not a regular file (or not there).
  static std::optional<FileStamp> of(const std::filesystem::path& file);
};

class FileHashCache {
 public:
  static constexpr std::int64_t kMaxEntries = 50000;

  /// The cache at `file` (made when missing). @throws mtg::Error when it cannot be opened.
  explicit FileHashCache(const std::filesystem::path& file,
                         std::chrono::nanoseconds settle = std::chrono::seconds(2));
  ~FileHashCache();
  FileHashCache(const FileHashCache&) = delete;
  FileHashCache& operator=(const FileHashCache&) = delete;

  /// The cache where the environment says (see above); nullptr when it is off or unusable.
  static std::unique_ptr<FileHashCache> open_default();

  /// The hash remembered for `file` at exactly `stamp`, if any. Thread-safe.
  std::optional<std::string> find(const std::filesystem::path& file, const FileStamp& stamp);
  /// Remembers `hash` for `file` at `stamp` unless the file changed within the settle time.
  /// Thread-safe; a failure turns the cache off (find() then finds nothing).
  void remember(const std::filesystem::path& file, const FileStamp& stamp, const std::string& hash);

  std::int64_t hits() const { return hits_.load(); }

 private:
  void turn_off(const std::string& why);

  std::mutex mutex_;
  std::unique_ptr<store::Database> db_;
  std::chrono::nanoseconds settle_;
  std::atomic<std::int64_t> hits_{0};
};

}  // namespace mtg::scene
