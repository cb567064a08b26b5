#include "orchestrator/remote/lease_book.h"

namespace mtg::orchestrator::remote {

const char* to_string(LeaseState state) {
  switch (state) {
    case LeaseState::kGranted: return "granted";
    case LeaseState::kDone: return "done";
    case LeaseState::kExpired: return "expired";
    case LeaseState::kRevoked: return "revoked";
  }
  return "?";
}

LeaseBook::LeaseBook(const std::filesystem::path& file) {
  db_ = std::make_unique<store::Database>(file, store::Database::Mode::kCreate);
  // WAL: a killed coordinator never leaves a torn book; each change is its own commit.
  db_->exec("PRAGMA journal_mode=WAL");
  db_->exec("PRAGMA synchronous=NORMAL");
  db_->exec(
      "CREATE TABLE IF NOT EXISTS leases (episode_id INTEGER NOT NULL, attempt INTEGER NOT NULL, "
      "worker TEXT NOT NULL, state TEXT NOT NULL, PRIMARY KEY (episode_id, attempt))");
}

void LeaseBook::grant(const LeaseRecord& l) {
  store::Statement q(*db_, "INSERT OR REPLACE INTO leases (episode_id, attempt, worker, state) VALUES (?,?,?,?)");
  q.bind(1, l.episode_id.value()).bind(2, std::int64_t{l.attempt}).bind(3, l.worker).bind(4, to_string(LeaseState::kGranted));
  q.run();
}

void LeaseBook::close(bus::EpisodeId episode_id, int attempt, LeaseState state) {
  store::Statement q(*db_, "UPDATE leases SET state = ? WHERE episode_id = ? AND attempt = ?");
  q.bind(1, to_string(state)).bind(2, episode_id.value()).bind(3, std::int64_t{attempt});
  q.run();
}

std::vector<LeaseRecord> LeaseBook::open_leases() const {
  store::Statement q(*db_, "SELECT episode_id, attempt, worker FROM leases WHERE state = ? ORDER BY episode_id");
  q.bind(1, to_string(LeaseState::kGranted));
  std::vector<LeaseRecord> out;
  while (q.step()) out.push_back({bus::EpisodeId(q.column_int(0)), static_cast<int>(q.column_int(1)), q.column_text(2)});
  return out;
}

std::map<bus::EpisodeId, int> LeaseBook::last_attempts() const {
  store::Statement q(*db_, "SELECT episode_id, MAX(attempt) FROM leases GROUP BY episode_id");
  std::map<bus::EpisodeId, int> out;
  while (q.step()) out[bus::EpisodeId(q.column_int(0))] = static_cast<int>(q.column_int(1));
  return out;
}

}  // namespace mtg::orchestrator::remote
