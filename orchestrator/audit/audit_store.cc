#include "orchestrator/audit/audit_store.h"

#include "core/util/error.h"

namespace mtg::orchestrator::audit {

namespace {

struct ReasonName {
  Reason reason;
  const char* name;
};
constexpr ReasonName kReasons[] = {{Reason::kOccluded, "occluded"},       {Reason::kUnclearNoun, "unclear_noun"},
                                   {Reason::kUnreadableMarks, "unreadable_marks"},
                                   {Reason::kAmbiguousText, "ambiguous_text"}, {Reason::kInfeasible, "infeasible"},
                                   {Reason::kOther, "other"}};

}  // namespace

const char* to_string(Reason r) {
  for (const ReasonName& n : kReasons) {
    if (n.reason == r) return n.name;
  }
  return "other";
}

Reason reason_from_string(const std::string& name) {
  std::string known;
  for (const ReasonName& n : kReasons) {
    if (name == n.name) return n.reason;
    known += std::string(known.empty() ? "" : ", ") + n.name;
  }
  throw Error("unknown reason '" + name + "' (one of " + known + ")");
}

const std::vector<Reason>& all_reasons() {
  static const std::vector<Reason> all = [] {
    std::vector<Reason> out;
    for (const ReasonName& n : kReasons) out.push_back(n.reason);
    return out;
  }();
  return all;
}

AuditStore::AuditStore(const std::filesystem::path& dir, bool create)
    : dir_(dir), db_(dir / "audit.sqlite", create ? store::Database::Mode::kCreate : store::Database::Mode::kReadWrite) {
  db_.exec("CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT)");
  db_.exec("CREATE TABLE IF NOT EXISTS items (idx INTEGER PRIMARY KEY, task_id TEXT, level INTEGER, page TEXT, truth TEXT)");
  db_.exec("CREATE TABLE IF NOT EXISTS answers (idx INTEGER, rater TEXT, valid INTEGER, reason TEXT, note TEXT, "
           "picks TEXT, seq INTEGER, PRIMARY KEY (idx, rater))");
  db_.exec("CREATE TABLE IF NOT EXISTS progress (idx INTEGER, rater TEXT, revealed INTEGER, picks TEXT, "
           "PRIMARY KEY (idx, rater))");
}

AuditStore::Progress AuditStore::progress(int index, const std::string& rater) {
  store::Statement q(db_, "SELECT revealed, picks FROM progress WHERE idx = ? AND rater = ?");
  q.bind(1, static_cast<std::int64_t>(index)).bind(2, rater);
  Progress p;
  if (!q.step()) return p;
  p.revealed = static_cast<int>(q.column_int(0));
  p.picks = nlohmann::json::parse(q.column_text(1)).get<std::map<std::string, std::string>>();
  return p;
}

void AuditStore::put_progress(int index, const std::string& rater, const Progress& p) {
  store::Statement put(db_, "INSERT OR REPLACE INTO progress (idx, rater, revealed, picks) VALUES (?, ?, ?, ?)");
  put.bind(1, static_cast<std::int64_t>(index))
      .bind(2, rater)
      .bind(3, static_cast<std::int64_t>(p.revealed))
      .bind(4, nlohmann::json(p.picks).dump())
      .run();
}

std::map<std::string, std::string> AuditStore::meta() {
  std::map<std::string, std::string> out;
  store::Statement q(db_, "SELECT key, value FROM meta");
  while (q.step()) out[q.column_text(0)] = q.column_text(1);
  return out;
}

void AuditStore::set_meta(const std::map<std::string, std::string>& values) {
  store::Transaction t(db_);
  store::Statement put(db_, "INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)");
  for (const auto& [k, v] : values) put.bind(1, k).bind(2, v).run();
  t.commit();
}

void AuditStore::add_item(const Item& item) {
  store::Statement put(db_, "INSERT OR REPLACE INTO items (idx, task_id, level, page, truth) VALUES (?, ?, ?, ?, ?)");
  put.bind(1, static_cast<std::int64_t>(item.index))
      .bind(2, item.task_id)
      .bind(3, static_cast<std::int64_t>(item.level))
      .bind(4, item.page.dump())
      .bind(5, item.truth.dump())
      .run();
}

std::vector<Item> AuditStore::items() {
  std::vector<Item> out;
  store::Statement q(db_, "SELECT idx, task_id, level, page, truth FROM items ORDER BY idx");
  while (q.step()) {
    out.push_back({static_cast<int>(q.column_int(0)), q.column_text(1), static_cast<int>(q.column_int(2)),
                   nlohmann::json::parse(q.column_text(3)), nlohmann::json::parse(q.column_text(4))});
  }
  return out;
}

std::optional<Item> AuditStore::item(int index) {
  store::Statement q(db_, "SELECT idx, task_id, level, page, truth FROM items WHERE idx = ?");
  q.bind(1, static_cast<std::int64_t>(index));
  if (!q.step()) return std::nullopt;
  return Item{static_cast<int>(q.column_int(0)), q.column_text(1), static_cast<int>(q.column_int(2)),
              nlohmann::json::parse(q.column_text(3)), nlohmann::json::parse(q.column_text(4))};
}

void AuditStore::put_answer(int index, const std::string& rater, const Answer& a) {
  store::Transaction t(db_);
  std::int64_t seq = 1;
  {
    store::Statement last(db_, "SELECT COALESCE(MAX(seq), 0) + 1 FROM answers");
    if (last.step()) seq = last.column_int(0);
  }
  store::Statement put(
      db_, "INSERT OR REPLACE INTO answers (idx, rater, valid, reason, note, picks, seq) VALUES (?, ?, ?, ?, ?, ?, ?)");
  put.bind(1, static_cast<std::int64_t>(index))
      .bind(2, rater)
      .bind(3, static_cast<std::int64_t>(a.valid ? 1 : 0))
      .bind(4, a.reason ? std::string(to_string(*a.reason)) : std::string())
      .bind(5, a.note)
      .bind(6, nlohmann::json(a.picks).dump())
      .bind(7, seq)
      .run();
  t.commit();
}

std::map<std::string, std::map<int, Answer>> AuditStore::all_answers() {
  std::map<std::string, std::map<int, Answer>> out;
  store::Statement q(db_, "SELECT idx, rater, valid, reason, note, picks, seq FROM answers ORDER BY rater, idx");
  while (q.step()) {
    Answer a;
    a.valid = q.column_int(2) != 0;
    const std::string reason = q.column_text(3);
    if (!reason.empty()) a.reason = reason_from_string(reason);
    a.note = q.column_text(4);
    a.picks = nlohmann::json::parse(q.column_text(5)).get<std::map<std::string, std::string>>();
    a.seq = q.column_int(6);
    out[q.column_text(1)][static_cast<int>(q.column_int(0))] = std::move(a);
  }
  return out;
}

std::map<int, Answer> AuditStore::answers(const std::string& rater) {
  auto all = all_answers();
  const auto it = all.find(rater);
  return it == all.end() ? std::map<int, Answer>{} : std::move(it->second);
}

}  // namespace mtg::orchestrator::audit
