#include "agents/vlm/response_cache.h"

#include "agents/vlm/encoding.h"
#include "core/util/error.h"

namespace mtg::vlm {

std::string cache_key(const std::string& url, const std::string& body) { return sha256_hex(url + "\n" + body); }

ResponseCache::ResponseCache(const std::filesystem::path& file) : file_(file) {
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
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
