#include "core/scene/dataset_fingerprint.h"

#include <fstream>
#include <optional>
#include <vector>

#include "core/util/error.h"
#include "core/util/hash.h"

namespace mtg::scene {
namespace {

namespace fs = std::filesystem;

std::string read_and_hash(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot read it to fingerprint the dataset");
  std::uint64_t h = kFnvOffset;
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    h = fnv1a64(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(buffer.data()), n), h);
  }
  return to_hex(h);
}

// The file's hash from the cache when it holds this very version, else read (and remembered when
// the file did not change while it was read).
std::string hash_of(const fs::path& file, FileHashCache* cache) {
  const auto before = FileStamp::of(file);
  if (!before) return kMissingFile;
  if (cache == nullptr) return read_and_hash(file);
  std::error_code ec;
  const fs::path key = fs::absolute(file, ec).lexically_normal();
  if (ec) return read_and_hash(file);
  if (auto kept = cache->find(key, *before)) return *kept;
  std::string hash = read_and_hash(file);
  if (FileStamp::of(file) == before) cache->remember(key, *before, hash);
  return hash;
}

std::string key_of(const fs::path& data_root, const fs::path& file) {
  const fs::path rel = file.lexically_normal().lexically_relative(data_root.lexically_normal());
  const bool inside = !rel.empty() && *rel.begin() != "..";
  return inside ? rel.generic_string() : file.lexically_normal().generic_string();
}

}  // namespace

std::string DatasetFingerprint::digest() const {
  std::uint64_t h = kFnvOffset;
  for (const auto& [path, hash] : files) h = fnv1a64(hash, fnv1a64(path + "\n", h));
  return to_hex(h);
}

nlohmann::json DatasetFingerprint::to_json() const { return files; }

DatasetFingerprint DatasetFingerprint::from_json(const nlohmann::json& j) {
  if (!j.is_object()) throw Error("dataset fingerprint: expected an object of file -> hash");
  DatasetFingerprint f;
  for (const auto& [path, hash] : j.items()) {
    if (!hash.is_string()) throw Error("dataset fingerprint: the hash of " + path + " is not a string");
    f.files[path] = hash.get<std::string>();
  }
  return f;
}

FileHashes::FileHashes() : cache_(FileHashCache::open_default()) {}

FileHashes::FileHashes(std::unique_ptr<FileHashCache> cache) : cache_(std::move(cache)) {}

FileHashes::~FileHashes() = default;

std::string FileHashes::of(const fs::path& file) {
  std::promise<std::string> mine;
  std::shared_future<std::string> hash;
  bool first = false;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto [it, inserted] = hashes_.try_emplace(file);
    if (inserted) it->second = mine.get_future().share();
    hash = it->second;
    first = inserted;
  }
  if (first) {  // this thread reads it; any other that asks meanwhile waits on `hash`
    try {
      mine.set_value(hash_of(file, cache_.get()));
    } catch (...) {
      mine.set_exception(std::current_exception());
    }
  }
  return hash.get();
}

DatasetFingerprint fingerprint_files(const fs::path& data_root, const std::set<fs::path>& files, FileHashes* hashes) {
  DatasetFingerprint f;
  std::optional<FileHashes> own;  // opens the hash cache: only when no reader is given
  FileHashes& reader = hashes ? *hashes : own.emplace();
  for (const fs::path& file : files) f.files[key_of(data_root, file)] = reader.of(file);
  return f;
}

std::string first_difference(const DatasetFingerprint& expected, const fs::path& data_root, FileHashes* hashes) {
  std::optional<FileHashes> own;  // opens the hash cache: only when no reader is given
  FileHashes& reader = hashes ? *hashes : own.emplace();
  for (const auto& [path, hash] : expected.files) {
    const fs::path file = fs::path(path).is_absolute() ? fs::path(path) : data_root / path;
    const std::string here = reader.of(file);
    if (here == hash) continue;
    if (here == kMissingFile) return path + " is missing here";
    if (hash == kMissingFile) return path + " is here but was missing where the tasks were made";
    return path + " differs";
  }
  return "";
}

std::string first_difference(const std::map<std::string, DatasetFingerprint>& by_scene, const fs::path& data_root) {
  FileHashes hashes;  // scenes share most files: each is read once
  for (const auto& [scene, fingerprint] : by_scene) {
    const std::string diff = first_difference(fingerprint, data_root, &hashes);
    if (!diff.empty()) return scene + ": " + diff;
  }
  return "";
}

nlohmann::json to_json(const std::map<std::string, DatasetFingerprint>& by_scene) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [scene, f] : by_scene) j[scene] = f.to_json();
  return j;
}

std::map<std::string, DatasetFingerprint> fingerprints_from_json(const nlohmann::json& j) {
  if (!j.is_object()) throw Error("dataset fingerprints: expected an object of scene -> files");
  std::map<std::string, DatasetFingerprint> out;
  for (const auto& [scene, files] : j.items()) out[scene] = DatasetFingerprint::from_json(files);
  return out;
}

}  // namespace mtg::scene
