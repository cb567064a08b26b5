#pragma once
// The response cache: answers keyed by SHA-256 of the request (URL and JSON body, which hold the
// model, the parameters, every message and the base64 of every image; never the key). A rerun
// of the same tasks and seed makes the same requests, so it costs no API call. Shared by every
// adapter process (SQLite in WAL mode) and by every thread of one (a mutex around the handle).

#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "agents/vlm/chat.h"
#include "core/store/sqlite.h"

namespace mtg::vlm {

class ResponseCache {
 public:
  /// Creates the file (and its folder) if needed. @throws mtg::Error naming the file.
  explicit ResponseCache(const std::filesystem::path& file);
  std::optional<ModelAnswer> get(const std::string& key);
  void put(const std::string& key, const std::string& bucket, const ModelAnswer& answer);
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  std::mutex mutex_;
  std::unique_ptr<store::Database> db_;
};

/// The cache key of a request.
std::string cache_key(const std::string& url, const std::string& body);

}  // namespace mtg::vlm
