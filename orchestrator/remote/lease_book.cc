#include "orchestrator/remote/lease_book.h"

#include "core/util/error.h"

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
  grant_ = std::make_unique<store::Statement>(
      *db_, "INSERT OR REPLACE INTO leases (episode_id, attempt, worker, state) VALUES (?,?,?,?)");
  close_ = std::make_unique<store::Statement>(*db_, "UPDATE leases SET state = ? WHERE episode_id = ? AND attempt = ?");
}

LeaseBook::~LeaseBook() {
  try {
    flush();
  } catch (const Error&) {
    // Nothing to do in a destructor: a resumed coordinator sees the book as it was last flushed.
  }
  grant_.reset();
  close_.reset();
}

void LeaseBook::grant(const LeaseRecord& l) { pending_.push_back({l, LeaseState::kGranted}); }

void LeaseBook::close(bus::EpisodeId episode_id, int attempt, LeaseState state) {
  pending_.push_back({{episode_id, attempt, ""}, state});
}

void LeaseBook::flush() {
  if (pending_.empty()) return;
  store::Transaction t(*db_);
  for (const Change& c : pending_) {
    store::Statement& q = c.state == LeaseState::kGranted ? *grant_ : *close_;
    q.reset();
    if (c.state == LeaseState::kGranted) {
      q.bind(1, c.lease.episode_id.value()).bind(2, std::int64_t{c.lease.attempt}).bind(3, c.lease.worker);
      q.bind(4, to_string(LeaseState::kGranted));
    } else {
      q.bind(1, to_string(c.state)).bind(2, c.lease.episode_id.value()).bind(3, std::int64_t{c.lease.attempt});
    }
    q.run();
  }
  t.commit();
  pending_.clear();
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
