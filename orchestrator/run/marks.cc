#include "orchestrator/run/marks.h"

#include <algorithm>

#include "core/store/sqlite.h"
#include "core/util/error.h"

namespace mtg::orchestrator {

namespace fs = std::filesystem;

namespace {

constexpr std::pair<MarkAction, const char*> kNames[] = {
    {MarkAction::kFlag, "flag"},       {MarkAction::kUnflag, "unflag"},   {MarkAction::kTag, "tag"},
    {MarkAction::kUntag, "untag"},     {MarkAction::kExclude, "exclude"}, {MarkAction::kInclude, "include"}};

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS marks (
  seq INTEGER PRIMARY KEY AUTOINCREMENT,
  episode_id INTEGER NOT NULL,
  action TEXT NOT NULL,
  tag TEXT NOT NULL,
  reason TEXT NOT NULL,
  who TEXT NOT NULL,
  at TEXT NOT NULL
);
)sql";

void check_text(const std::string& field, const std::string& value) {
  if (value.size() > kMarkTextLimit) {
    throw Error("mark: " + field + " is " + std::to_string(value.size()) + " bytes (at most " +
                std::to_string(kMarkTextLimit) + ")");
  }
  if (std::any_of(value.begin(), value.end(), [](unsigned char c) { return c < 0x20; })) {
    throw Error("mark: " + field + " holds a control character (one line of text)");
  }
}

}  // namespace

const char* to_string(MarkAction a) {
  for (const auto& [action, name] : kNames) {
    if (action == a) return name;
  }
  throw InternalError("a mark action without a name");
}

std::optional<MarkAction> mark_action_from_string(std::string_view name) {
  for (const auto& [action, n] : kNames) {
    if (name == n) return action;
  }
  return std::nullopt;
}

void check_mark(const MarkEntry& e) {
  if (!e.episode.valid()) throw Error("mark: no episode");
  if (e.who.empty()) throw Error("mark: 'who' is required (the name the trail keeps)");
  const bool tagging = e.action == MarkAction::kTag || e.action == MarkAction::kUntag;
  if (tagging && e.tag.empty()) throw Error("mark: a tag is required to " + std::string(to_string(e.action)));
  if (!tagging && !e.tag.empty()) throw Error(std::string("mark: a tag goes with tag or untag, not ") + to_string(e.action));
  // A reason of " " says nothing: it is as missing as an empty one (issue 55).
  const bool blank = e.reason.find_first_not_of(" \t\r\n") == std::string::npos;
  if ((e.action == MarkAction::kExclude || e.action == MarkAction::kInclude) && blank) {
    throw Error(std::string("mark: a reason is required to ") + to_string(e.action) + " an episode");
  }
  check_text("who", e.who);
  check_text("tag", e.tag);
  check_text("reason", e.reason);
}

void add_mark(const fs::path& run_dir, const MarkEntry& e) {
  check_mark(e);
  store::Database db(run_dir / "marks.sqlite", store::Database::Mode::kCreate);
  db.exec(kSchema);
  store::Statement q(db, "INSERT INTO marks (episode_id, action, tag, reason, who, at) VALUES (?, ?, ?, ?, ?, ?)");
  q.bind(1, e.episode.value()).bind(2, to_string(e.action)).bind(3, e.tag).bind(4, e.reason).bind(5, e.who).bind(6, e.at);
  q.run();
}

std::vector<MarkEntry> read_marks(const fs::path& run_dir) {
  const fs::path file = run_dir / "marks.sqlite";
  std::vector<MarkEntry> out;
  if (!fs::exists(file)) return out;
  store::Database db(file, store::Database::Mode::kReadOnly);
  store::Statement q(db, "SELECT episode_id, action, tag, reason, who, at FROM marks ORDER BY seq");
  while (q.step()) {
    const auto action = mark_action_from_string(q.column_text(1));
    if (!action) throw Error(file.string() + ": unknown mark action '" + q.column_text(1) + "'");
    out.push_back({bus::EpisodeId(q.column_int(0)), *action, q.column_text(2), q.column_text(3), q.column_text(4),
                   q.column_text(5)});
  }
  return out;
}

std::int64_t marks_version(const fs::path& run_dir) {
  const fs::path file = run_dir / "marks.sqlite";
  if (!fs::exists(file)) return 0;
  store::Database db(file, store::Database::Mode::kReadOnly);
  store::Statement q(db, "SELECT COALESCE(MAX(seq), 0) FROM marks");  // rows are only ever added
  return q.step() ? q.column_int(0) : 0;
}

std::map<bus::EpisodeId, EpisodeMarks> current_marks(const std::vector<MarkEntry>& trail) {
  std::map<bus::EpisodeId, EpisodeMarks> out;
  for (const MarkEntry& e : trail) {
    EpisodeMarks& m = out[e.episode];
    switch (e.action) {
      case MarkAction::kFlag: m.flagged = true; break;
      case MarkAction::kUnflag: m.flagged = false; break;
      case MarkAction::kTag: m.tags.insert(e.tag); break;
      case MarkAction::kUntag: m.tags.erase(e.tag); break;
      case MarkAction::kExclude:
        m.excluded = true;
        m.exclusion_reason = e.reason;
        break;
      case MarkAction::kInclude:
        m.excluded = false;
        m.exclusion_reason.clear();
        break;
    }
  }
  return out;
}

std::vector<EpisodeRow> without_excluded(const std::vector<EpisodeRow>& rows,
                                         const std::map<bus::EpisodeId, EpisodeMarks>& marks) {
  std::vector<EpisodeRow> kept;
  kept.reserve(rows.size());
  for (const EpisodeRow& r : rows) {
    const auto it = marks.find(r.episode_id);
    if (it == marks.end() || !it->second.excluded) kept.push_back(r);
  }
  return kept;
}

}  // namespace mtg::orchestrator
