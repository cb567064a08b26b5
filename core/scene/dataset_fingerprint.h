#pragma once
// What a task set was made from (DESIGN.md §7, "A task set knows its inputs"): every file each of
// its scenes was loaded from, by path relative to the dataset root, with a content hash (or
// "missing"). A run, and every worker of a multi-host run, compares its own dataset with it
// before the first episode: a copy that lacks a mesh or holds another version of a config would
// otherwise score the oracle's tasks as failures without a word.
//
// The hashes are FNV-1a 64 of the file contents: they catch a different or missing file, not a
// forgery (core/util/hash.h). Unchanged files' hashes are remembered between commands
// (file_hash_cache.h); the digest is the same as reading every file.

#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "core/scene/file_hash_cache.h"

namespace mtg::scene {

inline constexpr const char* kMissingFile = "missing";

struct DatasetFingerprint {
  /// Path relative to the dataset root -> hex content hash, or kMissingFile.
  std::map<std::string, std::string> files;

  /// One hash over every entry.
  std::string digest() const;
  /// {"<path>": "<hash>", ...}
  nlohmann::json to_json() const;
  /// @throws mtg::Error naming the field.
  static DatasetFingerprint from_json(const nlohmann::json& j);
};

/// The hashes of files read so far, for fingerprints of several scenes at once (the shipped
/// apartments share two thirds of their bytes): each file is read once, by whichever thread asks
/// first, while the others wait for it; files unchanged since an earlier command are not read at
/// all (file_hash_cache.h). Thread-safe.
class FileHashes {
 public:
  /// With the cache the environment names (FileHashCache::open_default).
  FileHashes();
  /// With `cache` (nullptr: every file is read).
  explicit FileHashes(std::unique_ptr<FileHashCache> cache);
  ~FileHashes();
  FileHashes(const FileHashes&) = delete;
  FileHashes& operator=(const FileHashes&) = delete;
  /// Files whose hash came from the cache so far.
  std::int64_t cached() const { return cache_ ? cache_->hits() : 0; }

  /// The file's hex content hash, or kMissingFile. @throws mtg::Error naming a file that exists
  /// but cannot be read (to every caller that asks for it).
  std::string of(const std::filesystem::path& file);

 private:
  std::unique_ptr<FileHashCache> cache_;
  std::mutex mutex_;
  std::map<std::filesystem::path, std::shared_future<std::string>> hashes_;
};

/// The fingerprint of `files` (absolute, under `data_root`; files elsewhere keep their absolute
/// path as key), reading them through `hashes` when given. @throws mtg::Error naming a file
/// that exists but cannot be read.
DatasetFingerprint fingerprint_files(const std::filesystem::path& data_root,
                                     const std::set<std::filesystem::path>& files, FileHashes* hashes = nullptr);

/// The same files under another root, fingerprinted again: "" when every file matches, else one
/// line naming the first that differs and how ("missing here", "differs").
std::string first_difference(const DatasetFingerprint& expected, const std::filesystem::path& data_root,
                             FileHashes* hashes = nullptr);

/// The first difference over several scenes' fingerprints ("apt_0: objects/x.glb is missing
/// here"), "" when all match.
std::string first_difference(const std::map<std::string, DatasetFingerprint>& by_scene,
                             const std::filesystem::path& data_root);

/// The fingerprints of several scenes as one JSON object {"<scene>": {...}}, and back.
nlohmann::json to_json(const std::map<std::string, DatasetFingerprint>& by_scene);
/// @throws mtg::Error naming the field.
std::map<std::string, DatasetFingerprint> fingerprints_from_json(const nlohmann::json& j);

}  // namespace mtg::scene
