#include "bus/recording_ref.h"

#include "core/util/error.h"
#include "core/util/file_bytes.h"

namespace mtg::bus {

namespace fs = std::filesystem;

namespace {

constexpr const char* kTable =
    "CREATE TABLE IF NOT EXISTS recordings (episode_id INTEGER PRIMARY KEY, attempt INTEGER NOT NULL, "
    "location TEXT NOT NULL, host TEXT NOT NULL, shared INTEGER NOT NULL, bytes INTEGER NOT NULL, "
    "sha256 TEXT NOT NULL)";

}  // namespace

RecordingRef reference_to(EpisodeId episode, int attempt, std::string location, std::string host, bool shared,
                          std::span<const std::uint8_t> bytes) {
  RecordingRef ref;
  ref.episode = episode;
  ref.attempt = attempt;
  ref.location = std::move(location);
  ref.host = std::move(host);
  ref.shared = shared;
  ref.bytes = static_cast<std::int64_t>(bytes.size());
  ref.sha256 = sha256_hex(bytes);
  return ref;
}

mtg::recording_ref_t to_message(const RecordingRef& ref) {
  mtg::recording_ref_t m{};
  m.location = ref.location;
  m.host = ref.host;
  m.shared = ref.shared;
  m.bytes = ref.bytes;
  m.sha256 = ref.sha256;
  return m;
}

RecordingRef from_message(const mtg::recording_ref_t& m) {
  RecordingRef r;
  r.episode = episode_of(m.header);
  r.attempt = m.header.attempt;
  r.location = m.location;
  r.host = m.host;
  r.shared = m.shared;
  r.bytes = m.bytes;
  r.sha256 = m.sha256;
  return r;
}

RecordingRef relative_to(RecordingRef ref, const fs::path& run_dir) {
  const fs::path file = fs::path(ref.location).lexically_normal();
  const fs::path rel = file.lexically_relative(run_dir.lexically_normal());
  if (file.is_absolute() && !rel.empty() && *rel.begin() != "..") ref.location = rel.string();
  return ref;
}

fs::path resolve(const RecordingRef& ref, const fs::path& run_dir) {
  const fs::path file(ref.location);
  return file.is_absolute() ? file : run_dir / file;
}

void create_recording_refs(store::Database& db) { db.exec(kTable); }

void store_recording_ref(store::Database& db, const RecordingRef& ref) {
  store::Statement q(db, "INSERT OR REPLACE INTO recordings (episode_id, attempt, location, host, shared, bytes, sha256) "
                         "VALUES (?,?,?,?,?,?,?)");
  q.bind(1, ref.episode.value()).bind(2, std::int64_t{ref.attempt}).bind(3, ref.location).bind(4, ref.host);
  q.bind(5, std::int64_t{ref.shared ? 1 : 0}).bind(6, ref.bytes).bind(7, ref.sha256);
  q.run();
}

std::vector<RecordingRef> read_recording_refs(const fs::path& results_file) {
  if (!fs::exists(results_file)) return {};
  store::Database db(results_file, store::Database::Mode::kReadOnly);
  {
    store::Statement has(db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = 'recordings'");
    if (!has.step()) return {};
  }
  store::Statement q(db, "SELECT episode_id, attempt, location, host, shared, bytes, sha256 FROM recordings "
                         "ORDER BY episode_id");
  std::vector<RecordingRef> out;
  while (q.step()) {
    RecordingRef r;
    r.episode = EpisodeId(q.column_int(0));
    r.attempt = static_cast<int>(q.column_int(1));
    r.location = q.column_text(2);
    r.host = q.column_text(3);
    r.shared = q.column_int(4) != 0;
    r.bytes = q.column_int(5);
    r.sha256 = q.column_text(6);
    out.push_back(std::move(r));
  }
  return out;
}

std::string recording_file_name(EpisodeId episode, int attempt) {
  return "E" + to_string(episode) + "-a" + std::to_string(attempt) + ".lcmlog";
}

std::string recording_misfit(const fs::path& file, const RecordingRef& ref) {
  if (file.filename() != recording_file_name(ref.episode, ref.attempt)) {
    return "is not named " + recording_file_name(ref.episode, ref.attempt) + ", as the attempt's recording is";
  }
  if (ref.bytes <= 0 || ref.bytes > kMaxRecordingBytes) {
    return "is said to have " + std::to_string(ref.bytes) + " bytes, outside 1 to " + std::to_string(kMaxRecordingBytes);
  }
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(file, ec);
  if (!ec && fs::is_symlink(st)) return "is a symbolic link, not the recording itself";
  if (!ec && fs::exists(st) && !fs::is_regular_file(st)) return "is not a regular file";
  return "";
}

std::string check_recording(const fs::path& file, const RecordingRef& ref) {
  const std::string what = "the recording of episode " + to_string(ref.episode) + " (attempt " +
                           std::to_string(ref.attempt) + ") " + file.string();
  // Before a byte is read: a reference to another file, or to more bytes than a recording holds,
  // is damage whatever the file holds.
  if (const std::string misfit = recording_misfit(file, ref); !misfit.empty()) return what + " " + misfit;
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (ec) {
    return what + " is missing" +
           (ref.shared ? std::string(" from the shared folder")
                       : " (kept on " + (ref.host.empty() ? std::string("its worker") : ref.host) +
                             "; `mtg gather` brings it into the run folder)");
  }
  if (static_cast<std::int64_t>(size) != ref.bytes) {
    return what + " has " + std::to_string(size) + " bytes, not the " + std::to_string(ref.bytes) + " stored with it";
  }
  std::vector<std::uint8_t> bytes;
  try {
    bytes = read_file_bytes(file);
  } catch (const Error&) {
    return what + " cannot be read";
  }
  if (sha256_hex(bytes) != ref.sha256) return what + " is damaged: its bytes are not the ones stored with it (SHA-256)";
  return "";
}

}  // namespace mtg::bus
