#include "core/tasks/task_db.h"

#include <fstream>
#include <optional>
#include <ostream>

#include "core/store/sqlite.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"

namespace mtg::tasks {
namespace fs = std::filesystem;
namespace {

constexpr const char* kFormat = "mtg-task-db/2";

constexpr const char* kSchema = R"sql(
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE tasks (
  id TEXT PRIMARY KEY,
  scene TEXT NOT NULL,
  level INTEGER NOT NULL,
  type TEXT NOT NULL,
  text TEXT NOT NULL,
  item TEXT NOT NULL,
  source TEXT NOT NULL,
  destination TEXT NOT NULL,
  anchors TEXT NOT NULL,
  direction TEXT NOT NULL,
  goal_json TEXT NOT NULL,
  subtasks_json TEXT NOT NULL,
  oracle_json TEXT NOT NULL,
  step_limit INTEGER NOT NULL,
  template_id TEXT NOT NULL,
  identify_json TEXT NOT NULL,
  placements_json TEXT NOT NULL,
  generator_version TEXT NOT NULL,
  config_hash TEXT NOT NULL,
  seed INTEGER NOT NULL
);
CREATE INDEX tasks_by_level ON tasks (scene, level);
CREATE TABLE votes (
  task_id TEXT NOT NULL REFERENCES tasks (id),
  voter TEXT NOT NULL,
  verdict TEXT NOT NULL,
  PRIMARY KEY (task_id, voter)
);
)sql";

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ",") + s;
  return out;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (!s.empty() && start <= s.size()) {
    const std::size_t end = s.find(',', start);
    out.push_back(s.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}


// One line for a database this version cannot use: which file, what it is, what to do.
void require_format(store::Database& db, const fs::path& file) {
  std::string format;
  try {
    store::Statement q(db, "SELECT value FROM meta WHERE key = 'format'");
    if (q.step()) format = q.column_text(0);
  } catch (const Error&) {
    throw Error(file.string() + ": not a task database (no meta table)");
  }
  if (format != kFormat) {
    throw Error(file.string() + ": task database format '" + format + "', this mtg reads '" + kFormat +
                "'; generate the task set again with `mtg tasks`");
  }
}

nlohmann::json subtasks_of(const Task& t) {
  if (t.goal.contains("sequence")) return t.goal["sequence"];
  if (t.goal.contains("outcome")) return t.goal["outcome"]["all"];
  return nlohmann::json::array();
}

}  // namespace

nlohmann::json task_to_json(const Task& t) {
  return {{"id", t.id},         {"scene", t.scene},       {"level", t.level},
          {"type", t.type},     {"text", t.text},         {"item", t.item},
          {"source", t.source}, {"destination", t.destination}, {"anchors", t.anchors},
          {"direction", t.direction}, {"goal", t.goal},   {"oracle", t.oracle},
          {"step_limit", t.step_limit}, {"template_id", t.template_id},
          {"identify", to_json(t.identify)}, {"placements", to_json(t.placements)}};
}

struct TaskDbWriter::Open {
  store::Database db;
  store::Transaction tx;
  store::Statement insert;
  std::vector<std::string> scenes;
  nlohmann::json dropped = nlohmann::json::object();
  std::map<std::string, scene::DatasetFingerprint> dataset;
  std::string hash;
  std::ofstream jsonl;

  Open(const fs::path& tmp, const TaskOptions& options)
      : db(fresh(tmp), store::Database::Mode::kCreate),
        tx(with_schema(db)),
        insert(db,
               "INSERT INTO tasks (id, scene, level, type, text, item, source, destination, anchors, "
               "direction, goal_json, subtasks_json, oracle_json, step_limit, template_id, "
               "identify_json, placements_json, generator_version, config_hash, seed) "
               "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)"),
        hash(options.config_hash()) {}

  // A stale .partial of an interrupted run goes first; the schema goes in before the transaction.
  static const fs::path& fresh(const fs::path& tmp) {
    fs::remove(tmp);
    return tmp;
  }
  static store::Database& with_schema(store::Database& db) {
    db.exec(kSchema);
    return db;
  }
};

TaskDbWriter::TaskDbWriter(const fs::path& file, const TaskOptions& options, const fs::path& jsonl)
    : file_(file), jsonl_(jsonl), options_(options), open_(std::make_unique<Open>(partial_path(file), options)) {
  if (!jsonl_.empty()) {
    open_->jsonl.open(partial_path(jsonl_), std::ios::binary | std::ios::trunc);
    if (!open_->jsonl) throw Error(jsonl_.string() + ": cannot write");
  }
}

TaskDbWriter::~TaskDbWriter() {
  if (!open_) return;
  open_.reset();  // rolls back
  std::error_code ignored;
  fs::remove(partial_path(file_), ignored);
  if (!jsonl_.empty()) fs::remove(partial_path(jsonl_), ignored);
}

void TaskDbWriter::add(const TaskSet& set) {
  Open& o = *open_;
  o.scenes.push_back(set.scene);
  o.dropped[set.scene] = set.dropped.to_json();
  o.dataset[set.scene] = set.dataset;
  for (const Task& t : set.tasks) {
    store::Statement& insert = o.insert;
    insert.bind(1, t.id).bind(2, t.scene).bind(3, std::int64_t{t.level}).bind(4, t.type).bind(5, t.text);
    insert.bind(6, t.item).bind(7, t.source).bind(8, t.destination).bind(9, join(t.anchors));
    insert.bind(10, t.direction).bind(11, t.goal.dump()).bind(12, subtasks_of(t).dump());
    insert.bind(13, nlohmann::json(t.oracle).dump()).bind(14, std::int64_t{t.step_limit});
    insert.bind(15, t.template_id).bind(16, to_json(t.identify).dump()).bind(17, to_json(t.placements).dump());
    insert.bind(18, std::string(kGeneratorVersion)).bind(19, o.hash);
    insert.bind(20, static_cast<std::int64_t>(options_.seed));
    insert.run();
    if (o.jsonl.is_open()) o.jsonl << task_to_json(t).dump() << '\n';
  }
  if (o.jsonl.is_open() && !o.jsonl) throw Error(jsonl_.string() + ": write failed");
}

void TaskDbWriter::finish(const std::vector<Vote>& votes) {
  Open& o = *open_;
  store::Statement meta(o.db, "INSERT INTO meta (key, value) VALUES (?, ?)");
  for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{
           {"format", kFormat},
           {"dropped", o.dropped.dump()},
           {"dataset", scene::to_json(o.dataset).dump()},
           {"generator_version", kGeneratorVersion},
           {"config_json", options_.to_json().dump()},
           {"config_hash", o.hash},
           {"seed", std::to_string(options_.seed)},
           {"scenes", join(o.scenes)}}) {
    meta.bind(1, k).bind(2, v).run();
  }
  store::Statement vote(o.db, "INSERT INTO votes (task_id, voter, verdict) VALUES (?, ?, ?)");
  for (const Vote& v : votes) vote.bind(1, v.task_id).bind(2, v.voter).bind(3, v.verdict).run();
  o.tx.commit();
  if (o.jsonl.is_open()) {
    o.jsonl.close();
    if (!o.jsonl) throw Error(jsonl_.string() + ": write failed");
  }
  open_.reset();
  fs::rename(partial_path(file_), file_);
  if (!jsonl_.empty()) fs::rename(partial_path(jsonl_), jsonl_);
}

void write_task_db(const fs::path& file, const std::vector<TaskSet>& sets, const std::vector<Vote>& votes,
                   const TaskOptions& options, const fs::path& jsonl) {
  TaskDbWriter writer(file, options, jsonl);
  for (const TaskSet& set : sets) writer.add(set);
  writer.finish(votes);
}

std::vector<Task> read_tasks(const fs::path& file, const std::set<int>& levels) {
  store::Database db(file, store::Database::Mode::kReadOnly);
  require_format(db, file);
  store::Statement q(db,
                     "SELECT id, scene, level, type, text, item, source, destination, anchors, direction, "
                     "goal_json, oracle_json, step_limit, template_id, identify_json, placements_json "
                     "FROM tasks ORDER BY id");
  std::vector<Task> out;
  while (q.step()) {
    Task t;
    t.level = static_cast<int>(q.column_int(2));
    if (!levels.empty() && levels.count(t.level) == 0) continue;
    t.id = q.column_text(0);
    t.scene = q.column_text(1);
    t.type = q.column_text(3);
    t.text = q.column_text(4);
    t.item = q.column_text(5);
    t.source = q.column_text(6);
    t.destination = q.column_text(7);
    t.anchors = split(q.column_text(8));
    t.direction = q.column_text(9);
    try {
      t.goal = nlohmann::json::parse(q.column_text(10));
      t.oracle = nlohmann::json::parse(q.column_text(11)).get<std::vector<std::string>>();
      t.identify = identifications_from_json(nlohmann::json::parse(q.column_text(14)));
      t.placements = oracle_placements_from_json(nlohmann::json::parse(q.column_text(15)));
    } catch (const nlohmann::json::exception&) {
      throw Error(file.string() + ": task " + t.id + ": malformed goal_json, oracle_json, identify_json or placements_json");
    } catch (const Error& e) {
      throw Error(file.string() + ": task " + t.id + ": " + e.what());
    }
    t.step_limit = static_cast<int>(q.column_int(12));
    t.template_id = q.column_text(13);
    out.push_back(std::move(t));
  }
  return out;
}

namespace {

// One entry of the meta table of a task database, or nullopt.
std::optional<std::string> meta_value(const fs::path& file, const std::string& key) {
  store::Database db(file, store::Database::Mode::kReadOnly);
  require_format(db, file);
  store::Statement q(db, "SELECT value FROM meta WHERE key = ?");
  q.bind(1, key);
  if (!q.step()) return std::nullopt;
  return q.column_text(0);
}

}  // namespace

std::map<std::string, scene::DatasetFingerprint> read_dataset_fingerprints(const fs::path& file) {
  const auto dataset = meta_value(file, "dataset");
  if (!dataset) return {};
  try {
    return scene::fingerprints_from_json(nlohmann::json::parse(*dataset));
  } catch (const std::exception& e) {
    throw Error(file.string() + ": malformed dataset fingerprint (" + e.what() + ")");
  }
}

nlohmann::json read_generator_config(const fs::path& file) {
  return nlohmann::json::parse(meta_value(file, "config_json").value_or("{}"), nullptr, false);
}

nlohmann::json task_db_stats(const fs::path& file) {
  store::Database db(file, store::Database::Mode::kReadOnly);
  require_format(db, file);
  nlohmann::json j;
  nlohmann::json levels = {{"1", 0}, {"2", 0}, {"3", 0}, {"4", 0}};
  nlohmann::json types = nlohmann::json::object(), scenes = nlohmann::json::object();
  std::int64_t total = 0;
  {
    store::Statement q(db, "SELECT scene, level, type, COUNT(*) FROM tasks GROUP BY scene, level, type ORDER BY scene, level, type");
    while (q.step()) {
      const std::string scene = q.column_text(0);
      const std::string level = std::to_string(q.column_int(1));
      const std::string type = q.column_text(2);
      const std::int64_t n = q.column_int(3);
      levels[level] = levels[level].get<std::int64_t>() + n;
      types[type] = types.value(type, std::int64_t{0}) + n;
      if (!scenes.contains(scene)) scenes[scene] = {{"1", 0}, {"2", 0}, {"3", 0}, {"4", 0}, {"total", 0}};
      scenes[scene][level] = scenes[scene][level].get<std::int64_t>() + n;
      scenes[scene]["total"] = scenes[scene]["total"].get<std::int64_t>() + n;
      total += n;
    }
  }
  nlohmann::json meta = nlohmann::json::object();
  {
    store::Statement q(db, "SELECT key, value FROM meta ORDER BY key");
    while (q.step()) meta[q.column_text(0)] = q.column_text(1);
  }
  j["levels"] = levels;
  j["types"] = types;
  j["scenes"] = scenes;
  j["total"] = total;
  j["dropped"] = meta.contains("dropped") ? nlohmann::json::parse(meta["dropped"].get<std::string>())
                                          : nlohmann::json::object();
  meta.erase("dropped");
  meta.erase("dataset");  // file hashes: read_dataset_fingerprints
  j["meta"] = meta;
  return j;
}

}  // namespace mtg::tasks
