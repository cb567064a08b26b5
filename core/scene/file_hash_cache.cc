#include "core/scene/file_hash_cache.h"

#include <sys/stat.h>

#include <cstdlib>

#include "core/store/sqlite.h"
#include "core/util/error.h"
#include "core/util/log.h"

namespace mtg::scene {
namespace {

namespace fs = std::filesystem;

std::int64_t ns_of(const timespec& t) { return static_cast<std::int64_t>(t.tv_sec) * 1000000000 + t.tv_nsec; }

fs::path default_folder() {
  if (const char* dir = std::getenv("MTG_CACHE_DIR"); dir != nullptr && *dir != '\0') return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') return fs::path(xdg) / "mtg";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') return fs::path(home) / ".cache" / "mtg";
  return {};
}

}  // namespace

std::optional<FileStamp> FileStamp::of(const fs::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  return FileStamp{static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino),
                   static_cast<std::int64_t>(st.st_size), ns_of(st.st_mtim), ns_of(st.st_ctim)};
}

FileHashCache::FileHashCache(const fs::path& file, std::chrono::nanoseconds settle)
    : db_(std::make_unique<store::Database>(file, store::Database::Mode::kCreate)), settle_(settle) {
  db_->exec("PRAGMA journal_mode=WAL");
  db_->exec("PRAGMA synchronous=OFF");  // a cache: a torn write costs a re-read, never a wrong hash
  db_->exec(
      "CREATE TABLE IF NOT EXISTS file_hash (path TEXT PRIMARY KEY, device INTEGER, inode INTEGER, size INTEGER,"
      " modified_ns INTEGER, changed_ns INTEGER, hash TEXT)");
  store::Statement count(*db_, "SELECT count(*) FROM file_hash");
  if (count.step() && count.column_int(0) > kMaxEntries) db_->exec("DELETE FROM file_hash");
}

FileHashCache::~FileHashCache() = default;

std::unique_ptr<FileHashCache> FileHashCache::open_default() {
  const char* env = std::getenv("MTG_CACHE_DIR");
  if (env != nullptr && std::string(env) == "off") return nullptr;
  const fs::path folder = default_folder();
  if (folder.empty()) return nullptr;
  try {
    std::error_code ec;
    fs::create_directories(folder, ec);
    return std::make_unique<FileHashCache>(folder / "file-hashes.sqlite");
  } catch (const Error& e) {
    log::debug(std::string("dataset hash cache off: ") + e.what());
    return nullptr;
  }
}

std::optional<std::string> FileHashCache::find(const fs::path& file, const FileStamp& stamp) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!db_) return std::nullopt;
  try {
    store::Statement q(*db_,
                       "SELECT device, inode, size, modified_ns, changed_ns, hash FROM file_hash WHERE path = ?");
    q.bind(1, file.string());
    if (!q.step()) return std::nullopt;
    const FileStamp kept{static_cast<std::uint64_t>(q.column_int(0)), static_cast<std::uint64_t>(q.column_int(1)),
                         q.column_int(2), q.column_int(3), q.column_int(4)};
    const std::string hash = q.column_text(5);
    if (!(kept == stamp) || hash.size() != 16) return std::nullopt;
    ++hits_;
    return hash;
  } catch (const Error& e) {
    turn_off(e.what());
    return std::nullopt;
  }
}

void FileHashCache::remember(const fs::path& file, const FileStamp& stamp, const std::string& hash) {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  if (std::chrono::nanoseconds(now).count() - stamp.changed_ns < settle_.count()) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!db_) return;
  try {
    store::Statement q(*db_, "INSERT OR REPLACE INTO file_hash VALUES (?, ?, ?, ?, ?, ?, ?)");
    q.bind(1, file.string())
        .bind(2, static_cast<std::int64_t>(stamp.device))
        .bind(3, static_cast<std::int64_t>(stamp.inode))
        .bind(4, stamp.size)
        .bind(5, stamp.modified_ns)
        .bind(6, stamp.changed_ns)
        .bind(7, hash);
    q.run();
  } catch (const Error& e) {
    turn_off(e.what());
  }
}

void FileHashCache::turn_off(const std::string& why) {
  log::debug("dataset hash cache off: " + why);
  db_.reset();
}

}  // namespace mtg::scene
