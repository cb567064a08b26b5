#include "agents/vlm/response_cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "agents/vlm/encoding.h"
#include "core/util/error.h"

namespace mtg::vlm {

std::string cache_key(const std::string& url, const std::string& body) { return sha256_hex(url + "\n" + body); }

ResponseCache::ResponseCache(const std::filesystem::path& file) : file_(file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (file.has_parent_path() && !fs::exists(file.parent_path())) {
    fs::create_directories(file.parent_path(), ec);
    fs::permissions(file.parent_path(), fs::perms::owner_all, ec);  // a new folder: ours alone
  }
  // Answers may quote what was sent: the file is the owner's alone (SQLite gives its journal
  // files the same mode). An existing cache is tightened too.
  const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  if (fd < 0) throw Error(file.string() + ": cannot open the response cache: " + std::strerror(errno));
  ::fchmod(fd, 0600);
  ::close(fd);
  db_ = std::make_unique<store::Database>(file, store::Database::Mode::kCreate);
  // Several adapter processes write at once: WAL lets readers go on, and a writer waits its turn.
  db_->exec("PRAGMA busy_timeout=30000");
  db_->exec("PRAGMA journal_mode=WAL");
  db_->exec(
      "CREATE TABLE IF NOT EXISTS responses (key TEXT PRIMARY KEY, bucket TEXT NOT NULL, text TEXT NOT NULL, "
      "input_tokens INTEGER NOT NULL, output_tokens INTEGER NOT NULL)");
}

std::optional<ModelAnswer> ResponseCache::get(const std::string& key) {
  std::lock_guard lock(mutex_);
  store::Statement q(*db_, "SELECT text, input_tokens, output_tokens FROM responses WHERE key = ?");
  q.bind(1, key);
  if (!q.step()) return std::nullopt;
  return ModelAnswer{q.column_text(0), static_cast<int>(q.column_int(1)), static_cast<int>(q.column_int(2))};
}

void ResponseCache::put(const std::string& key, const std::string& bucket, const ModelAnswer& answer) {
  std::lock_guard lock(mutex_);
  store::Statement q(*db_,
                     "INSERT OR IGNORE INTO responses (key, bucket, text, input_tokens, output_tokens) VALUES (?,?,?,?,?)");
  q.bind(1, key).bind(2, bucket).bind(3, answer.text).bind(4, std::int64_t{answer.input_tokens});
  q.bind(5, std::int64_t{answer.output_tokens});
  q.run();
}

}  // namespace mtg::vlm
