#include "orchestrator/run/results_db.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iterator>
#include <set>

#include "core/util/error.h"

namespace mtg::orchestrator {
namespace {

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS episodes (
  episode_id INTEGER PRIMARY KEY,
  task_id TEXT NOT NULL, scene TEXT NOT NULL, level INTEGER NOT NULL, task_type TEXT NOT NULL,
  agent TEXT NOT NULL, attempt INTEGER NOT NULL,
  success INTEGER NOT NULL, ip REAL NOT NULL, stage TEXT NOT NULL, cause TEXT NOT NULL,
  steps INTEGER NOT NULL, invalid_actions INTEGER NOT NULL,
  input_tokens INTEGER NOT NULL, output_tokens INTEGER NOT NULL, cost_usd REAL NOT NULL,
  latency_ms REAL NOT NULL, wall_ms REAL NOT NULL,
  subtask_ip TEXT NOT NULL, detail TEXT NOT NULL, status TEXT NOT NULL,
  spent_usd REAL NOT NULL DEFAULT 0, images_sent INTEGER NOT NULL DEFAULT 0,
  model_calls INTEGER NOT NULL DEFAULT 0, cache_hits INTEGER NOT NULL DEFAULT 0,
  prompt_version TEXT NOT NULL DEFAULT '',
  worker TEXT NOT NULL DEFAULT ''
);
)sql";

// Columns added after the first schema: a results file of an older run gains them on open, so
// resuming it keeps working.
constexpr const char* kAddedColumns[][2] = {
    {"spent_usd", "REAL NOT NULL DEFAULT 0"},     {"images_sent", "INTEGER NOT NULL DEFAULT 0"},
    {"model_calls", "INTEGER NOT NULL DEFAULT 0"}, {"cache_hits", "INTEGER NOT NULL DEFAULT 0"},
    {"prompt_version", "TEXT NOT NULL DEFAULT ''"}, {"worker", "TEXT NOT NULL DEFAULT ''"}};

constexpr const char* kColumns =
    "episode_id, task_id, scene, level, task_type, agent, attempt, success, ip, stage, cause, steps, "
    "invalid_actions, input_tokens, output_tokens, cost_usd, latency_ms, wall_ms, subtask_ip, detail, status, "
    "spent_usd, images_sent, model_calls, cache_hits, prompt_version, worker";

// A value no judge writes (NaN, an infinity, a level of 99, text in a number column) is damage: it
// would print "[-nan, -nan]" or an 80-digit figure, or make a row of a level that does not exist.
// One line naming the row, rather than figures computed from it (issue 55).
void check_row(const store::Statement& q, const EpisodeRow& r, const std::filesystem::path& file) {
  const auto bad = [&](const std::string& what) {
    throw Error(file.string() + ": episode " + std::to_string(r.episode_id.value()) + ": " + what +
                "; the results are damaged (no judge writes that)");
  };
  constexpr int kNumbers[] = {0, 3, 6, 7, 8, 11, 12};  // episode_id, level, attempt, success, ip, steps, invalid_actions
  constexpr const char* kNames[] = {"episode_id", "level", "attempt", "success", "ip", "steps", "invalid_actions"};
  for (std::size_t i = 0; i < std::size(kNumbers); ++i) {
    if (!q.column_is_number(kNumbers[i])) bad(std::string(kNames[i]) + " is not a number");
  }
  if (r.level < 1 || r.level > 4) bad("level " + std::to_string(r.level) + " is not 1 to 4");
  if (!std::isfinite(r.ip) || r.ip < 0.0 || r.ip > 100.0) bad("ip " + std::to_string(r.ip) + " is not between 0 and 100");
  if (r.steps < 0 || r.invalid_actions < 0 || r.attempt < 0) bad("a negative count");
  if (!std::isfinite(r.usage.cost_usd) || !std::isfinite(r.usage.spent_usd) || r.usage.cost_usd < 0 || r.usage.spent_usd < 0) {
    bad("a cost that is not a finite amount");
  }
}

std::vector<EpisodeRow> select_rows(store::Database& db) {
  store::Statement q(db, std::string("SELECT ") + kColumns + " FROM episodes ORDER BY episode_id");
  std::vector<EpisodeRow> out;
  while (q.step()) {
    EpisodeRow r;
    r.episode_id = bus::EpisodeId(q.column_int(0));
    r.task_id = q.column_text(1);
    r.scene = q.column_text(2);
    r.level = static_cast<int>(q.column_int(3));
    r.task_type = q.column_text(4);
    r.agent = q.column_text(5);
    r.attempt = static_cast<int>(q.column_int(6));
    r.success = q.column_int(7) != 0;
    r.ip = q.column_double(8);
    r.stage = q.column_text(9);
    r.cause = q.column_text(10);
    r.steps = static_cast<int>(q.column_int(11));
    r.invalid_actions = static_cast<int>(q.column_int(12));
    r.usage.input_tokens = q.column_int(13);
    r.usage.output_tokens = q.column_int(14);
    r.usage.cost_usd = q.column_double(15);
    r.usage.latency_ms = q.column_double(16);
    r.wall_ms = q.column_double(17);
    r.subtask_ip = q.column_text(18);
    r.detail = q.column_text(19);
    r.status = q.column_text(20);
    r.usage.spent_usd = q.column_double(21);
    r.usage.images_sent = q.column_int(22);
    r.usage.model_calls = q.column_int(23);
    r.usage.cache_hits = q.column_int(24);
    r.usage.prompt_version = q.column_text(25);
    r.worker = q.column_text(26);
    check_row(q, r, db.file());
    out.push_back(std::move(r));
  }
  return out;
}

void add_missing_columns(store::Database& db) {
  std::set<std::string> have;
  store::Statement q(db, "PRAGMA table_info(episodes)");
  while (q.step()) have.insert(q.column_text(1));
  for (const auto& [name, type] : kAddedColumns) {
    if (have.count(name) == 0) db.exec(std::string("ALTER TABLE episodes ADD COLUMN ") + name + " " + type);
  }
}

}  // namespace

void set_verdict(EpisodeRow& row, const mtg::episode_result_t& result) {
  row.success = result.success;
  row.ip = result.ip;
  row.stage = result.stage;
  row.cause = result.cause;
  row.steps = result.steps;
  row.invalid_actions = result.invalid_actions;
  row.subtask_ip = nlohmann::json(result.subtask_ip).dump();
  row.detail = result.detail;
}

ResultsDb::ResultsDb(const std::filesystem::path& file) : file_(file) {
  db_ = std::make_unique<store::Database>(file, store::Database::Mode::kCreate);
  // WAL: a killed orchestrator never leaves a torn database; every insert is its own commit.
  db_->exec("PRAGMA journal_mode=WAL");
  db_->exec("PRAGMA synchronous=NORMAL");
  db_->exec(kSchema);
  add_missing_columns(*db_);
  bus::create_recording_refs(*db_);
  // A verdict is written once; a row of an episode given up (status "error") gives way to a
  // later attempt's row, so a resume that runs it again stores what it gave.
  insert_ = std::make_unique<store::Statement>(
      *db_, std::string("INSERT OR REPLACE INTO episodes (") + kColumns +
                ") SELECT ?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,? WHERE NOT EXISTS "
                "(SELECT 1 FROM episodes WHERE episode_id = ?1 AND status <> 'error')");
}

ResultsDb::~ResultsDb() {
  insert_.reset();  // no statement may stay prepared while the journal mode changes
  try {
    db_->exec("PRAGMA journal_mode=DELETE");
  } catch (const Error&) {
    // Another reader holds the file: the WAL stays and SQLite recovers it on the next open.
  }
}

bool ResultsDb::insert(const EpisodeRow& r, const bus::RecordingRef* recording) {
  if (recording == nullptr) return insert_row(r);
  // The verdict and where its recording is, together or not at all.
  store::Transaction t(*db_);
  const bool written = insert_row(r);
  if (written) store_recording_ref(*db_, *recording);
  t.commit();
  return written;
}

bool ResultsDb::insert_row(const EpisodeRow& r) {
  store::Statement& q = *insert_;
  q.reset();  // after a failed insert too
  q.bind(1, r.episode_id.value()).bind(2, r.task_id).bind(3, r.scene).bind(4, std::int64_t{r.level}).bind(5, r.task_type);
  q.bind(6, r.agent).bind(7, std::int64_t{r.attempt}).bind(8, std::int64_t{r.success ? 1 : 0}).bind(9, r.ip);
  q.bind(10, r.stage).bind(11, r.cause).bind(12, std::int64_t{r.steps}).bind(13, std::int64_t{r.invalid_actions});
  q.bind(14, r.usage.input_tokens).bind(15, r.usage.output_tokens).bind(16, r.usage.cost_usd).bind(17, r.usage.latency_ms);
  q.bind(18, r.wall_ms).bind(19, r.subtask_ip).bind(20, r.detail).bind(21, r.status);
  q.bind(22, r.usage.spent_usd).bind(23, r.usage.images_sent).bind(24, r.usage.model_calls);
  q.bind(25, r.usage.cache_hits).bind(26, r.usage.prompt_version).bind(27, r.worker);
  q.run();
  return db_->changes() > 0;
}

std::vector<EpisodeRow> ResultsDb::rows() const { return select_rows(*db_); }

std::vector<EpisodeRow> read_results(const std::filesystem::path& file) {
  store::Database db(file, store::Database::Mode::kReadOnly);
  return select_rows(db);
}

std::string verdict_fingerprint(const EpisodeRow& r) {
  char ip[32];
  std::snprintf(ip, sizeof(ip), "%.6f", r.ip);
  return to_string(r.episode_id) + "|" + r.task_id + "|" + std::to_string(r.level) + "|" +
         (r.success ? "1" : "0") + "|" + ip + "|" + r.stage + "|" + r.cause + "|" + std::to_string(r.steps) + "|" +
         std::to_string(r.invalid_actions) + "|" + r.subtask_ip + "|" + r.status;
}

}  // namespace mtg::orchestrator
