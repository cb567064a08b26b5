#include "core/tasks/task_db.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <ostream>
#include <set>

#include "core/store/sqlite.h"
#include "core/tasks/coverage.h"
#include "core/tasks/suite.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "core/util/json_writer.h"
#include "core/util/parallel.h"
#include "core/util/zlib_bytes.h"

namespace mtg::tasks {
namespace fs = std::filesystem;
namespace {

constexpr const char* kFormat = "mtg-task-db/3";

// Tasks are stored 64 to a chunk, as one zlib-compressed JSON array (each element the task's
// JSONL object): about 110 B a task against 1,470 B as plain columns, since the names, phrases
// and keys repeat across neighbouring tasks. `tasks` keeps what queries filter on, uncompressed.
// The view gives each task's JSON back in the stock sqlite3 shell (its sqlar_uncompress); mtg
// itself reads the chunks.
constexpr std::size_t kTasksPerChunk = 64;
// zlib's level for the chunks. Measured on the three shipped apartments' 107 MB of task JSON:
// level 6 (zlib's default) takes 2.2 s of CPU for 118 B a task (190 B with the index rows),
// level 3 0.95 s for 144 B (204 B). Well under 250 B a task; the time was an eighth of
// generating the three.
constexpr int kChunkLevel = 3;

constexpr const char* kSchema = R"sql(
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE tasks (
  id TEXT PRIMARY KEY,
  scene TEXT NOT NULL,
  level INTEGER NOT NULL,
  type TEXT NOT NULL,
  chunk INTEGER NOT NULL,
  slot INTEGER NOT NULL
) WITHOUT ROWID;
CREATE TABLE task_chunks (
  chunk INTEGER PRIMARY KEY,
  size INTEGER NOT NULL,
  body BLOB NOT NULL
);
CREATE VIEW task_json AS
  SELECT t.id AS id, t.scene AS scene, t.level AS level, t.type AS type,
         json_extract(CAST(sqlar_uncompress(c.body, c.size) AS TEXT), '$[' || t.slot || ']') AS task
  FROM tasks t JOIN task_chunks c ON c.chunk = t.chunk;
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

}  // namespace

nlohmann::json task_to_json(const Task& t) {
  return {{"id", t.id},
          {"scene", t.scene},
          {"level", t.level},
          {"type", t.type},
          {"text", t.text},
          {"item", t.item},
          {"source", t.source},
          {"destination", t.destination},
          {"anchors", t.anchors},
          {"direction", t.direction},
          {"goal", t.goal},
          {"oracle", t.oracle},
          {"step_limit", t.step_limit},
          {"template_id", t.template_id},
          {"identify", to_json(t.identify)},
          {"placements", to_json(t.placements)}};
}

namespace {

// The members in the order dump() prints them (task_to_json's, sorted).
void write_reference(JsonWriter& w, const Reference& r) {
  w.begin_object();
  if (!r.landmark.empty()) w.key("landmark").value(r.landmark);
  w.key("noun").value(r.noun);
  if (r.rank > 0) w.key("rank").value(r.rank);
  w.key("relation").value(to_string(r.relation));
  if (r.row != Row::kNone) w.key("row").value(r.row == Row::kFront ? "near" : "far");
  if (r.stack > 0) w.key("stack").value(r.stack);
  if (r.stack_from_right) w.key("stack_from").value("right");
  w.end_object();
}

void write_identification(JsonWriter& w, const Identification& id) {
  w.begin_object();
  w.key("object").value(id.object);
  w.key("part").value(id.part);
  w.key("phrase").value(id.phrase);
  w.key("platform").value(id.platform);
  w.key("reference");
  write_reference(w, id.reference);
  w.key("role").value(id.role);
  w.end_object();
}

void write_placement(JsonWriter& w, const OraclePlacement& p) {
  w.begin_object();
  w.key("margin").value(p.margin);  // null when unbounded, as in to_json
  w.key("object").value(p.object);
  w.key("part").value(p.part);
  w.key("platform").value(p.platform);
  w.key("x").value(p.position.x());
  w.key("y").value(p.position.y());
  w.key("z").value(p.position.z());
  w.end_object();
}

}  // namespace

void append_task_json(std::string& out, const Task& t) {
  JsonWriter w(out);
  w.begin_object();
  w.key("anchors").array(t.anchors);
  w.key("destination").value(t.destination);
  w.key("direction").value(t.direction);
  w.key("goal").document(t.goal);
  w.key("id").value(t.id);
  w.key("identify").begin_array();
  for (const Identification& id : t.identify) write_identification(w, id);
  w.end_array();
  w.key("item").value(t.item);
  w.key("level").value(t.level);
  w.key("oracle").array(t.oracle);
  w.key("placements").begin_array();
  for (const OraclePlacement& p : t.placements) write_placement(w, p);
  w.end_array();
  w.key("scene").value(t.scene);
  w.key("source").value(t.source);
  w.key("step_limit").value(t.step_limit);
  w.key("template_id").value(t.template_id);
  w.key("text").value(t.text);
  w.key("type").value(t.type);
  w.end_object();
}

Task task_from_json(const nlohmann::json& j) {
  for (const char* key : {"id", "scene", "level", "type", "text", "item", "source", "destination", "anchors",
                          "direction", "goal", "oracle", "step_limit", "template_id", "identify", "placements"}) {
    if (!j.contains(key)) throw Error(std::string("task: missing field '") + key + "'");
  }
  Task t;
  try {
    t.id = j["id"].get<std::string>();
    t.scene = j["scene"].get<std::string>();
    t.level = json_integer<int>(j["level"], "level");
    t.type = j["type"].get<std::string>();
    t.text = j["text"].get<std::string>();
    t.item = j["item"].get<std::string>();
    t.source = j["source"].get<std::string>();
    t.destination = j["destination"].get<std::string>();
    t.anchors = j["anchors"].get<std::vector<std::string>>();
    t.direction = j["direction"].get<std::string>();
    t.goal = j["goal"];
    t.oracle = j["oracle"].get<std::vector<std::string>>();
    t.step_limit = json_integer<int>(j["step_limit"], "step_limit");
    t.template_id = j["template_id"].get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    const std::string id = j["id"].is_string() ? j["id"].get<std::string>() : std::string("?");
    throw Error("task " + id + ": a field has the wrong type (" + e.what() + ")");
  } catch (const Error& e) {
    throw Error("task " + (j["id"].is_string() ? j["id"].get<std::string>() : std::string("?")) + ": " + e.what());
  }
  // A database is input like any other: a step limit of 10^8 or a 4 MB text would make planning
  // and prompts take gigabytes before anything said why.
  if (t.level < 1 || t.level > 4) throw Error("task " + t.id + ": level " + std::to_string(t.level) + " is not 1-4");
  if (t.step_limit < 1 || t.step_limit > kMaxStepLimit) {
    throw Error("task " + t.id + ": step_limit " + std::to_string(t.step_limit) + " is not in 1.." +
                std::to_string(kMaxStepLimit));
  }
  if (t.text.size() > kMaxTaskText) {
    throw Error("task " + t.id + ": its text has " + std::to_string(t.text.size()) + " bytes, more than the " +
                std::to_string(kMaxTaskText) + " a task text may have");
  }
  try {
    t.identify = identifications_from_json(j["identify"]);
    t.placements = oracle_placements_from_json(j["placements"]);
  } catch (const nlohmann::json::exception& e) {
    // Found by scripts/fuzz: a look-alike record with a field of the wrong type ended the program.
    throw Error("task " + t.id + ": its identify or placements records are malformed (" + e.what() + ")");
  } catch (const Error& e) {
    throw Error("task " + t.id + ": " + e.what());
  }
  return t;
}

struct TaskDbWriter::Open {
  store::Database db;
  store::Transaction tx;
  store::Statement insert_task;
  store::Statement insert_chunk;
  std::int64_t next_chunk = 0;
  std::vector<std::string> scenes;
  nlohmann::json dropped = nlohmann::json::object();
  nlohmann::json coverage = nlohmann::json::object();
  nlohmann::json warnings = nlohmann::json::object();
  std::map<std::string, scene::DatasetFingerprint> dataset;
  std::string hash;
  std::ofstream jsonl;

  Open(const fs::path& tmp, const TaskOptions& options)
      : db(tmp, store::Database::Mode::kCreate),
        tx(with_schema(db)),
        insert_task(db, "INSERT INTO tasks (id, scene, level, type, chunk, slot) VALUES (?,?,?,?,?,?)"),
        insert_chunk(db, "INSERT INTO task_chunks (chunk, size, body) VALUES (?,?,?)"),
        hash(options.config_hash()) {}

  // The schema goes in before the transaction.
  static store::Database& with_schema(store::Database& db) {
    db.exec(kSchema);
    return db;
  }
};

TaskDbWriter::TaskDbWriter(const fs::path& file, const TaskOptions& options, const fs::path& jsonl, int jobs)
    : file_(file),
      jsonl_(jsonl),
      options_(options),
      jobs_(jobs),
      db_partial_(file, PartialFile::Stale::kRemove),
      open_(std::make_unique<Open>(db_partial_.path(), options)) {
  if (!jsonl_.empty()) {
    jsonl_partial_.emplace(jsonl_, PartialFile::Stale::kRemove);
    open_->jsonl.open(jsonl_partial_->path(), std::ios::binary | std::ios::trunc);
    if (!open_->jsonl) throw Error(jsonl_.string() + ": cannot write");
  }
}

// Without finish(), the transaction rolls back and the partial files go.
TaskDbWriter::~TaskDbWriter() = default;

void TaskDbWriter::end_scene(const TaskSet& set) {
  MTG_DEMAND(set.tasks.empty(), "end_scene() takes a scene whose tasks were stored; add() takes a whole one");
  Open& o = *open_;
  o.scenes.push_back(set.scene);
  o.dropped[set.scene] = set.dropped.to_json();
  o.coverage[set.scene] = set.coverage;
  o.warnings[set.scene] = set.warnings;
  o.dataset[set.scene] = set.dataset;
  scene_open_ = false;
}

void TaskDbWriter::add(const TaskSet& set) {
  // A batch of chunks at a time, so the text of a whole set is never held.
  constexpr std::size_t kBatch = 64 * kTasksPerChunk;
  for (std::size_t at = 0; at < set.tasks.size(); at += kBatch) {
    std::vector<Task> batch(set.tasks.begin() + static_cast<std::ptrdiff_t>(at),
                            set.tasks.begin() + static_cast<std::ptrdiff_t>(std::min(set.tasks.size(), at + kBatch)));
    store(make_chunks(batch, true));  // only the set's last batch can end in a short chunk
  }
  TaskSet meta;
  meta.scene = set.scene;
  meta.dropped = set.dropped;
  meta.coverage = set.coverage;
  meta.warnings = set.warnings;
  meta.dataset = set.dataset;
  end_scene(meta);
}

std::vector<TaskChunk> TaskDbWriter::make_chunks(std::vector<Task>& tasks, bool last) const {
  // Each chunk is made alone (so the bytes do not depend on the threads) from its 64 tasks,
  // counted from the scene's first: a chunk never spans two scenes, and a scene's chunks are the
  // same however its tasks were batched, because only whole chunks are made before its end.
  const std::size_t n_chunks = last ? (tasks.size() + kTasksPerChunk - 1) / kTasksPerChunk : tasks.size() / kTasksPerChunk;
  const std::size_t n_taken = std::min(tasks.size(), n_chunks * kTasksPerChunk);
  std::vector<TaskChunk> chunks(n_chunks);
  parallel_for(chunks.size(), jobs_, [&](std::size_t c) {
    TaskChunk& chunk = chunks[c];
    const std::size_t begin = c * kTasksPerChunk, end = std::min(n_taken, begin + kTasksPerChunk);
    std::string json = "[";
    for (std::size_t i = begin; i < end; ++i) {
      const Task& t = tasks[i];
      chunk.rows.push_back({t.id, t.scene, t.type, t.level});
      if (json.size() > 1) json += ',';
      const std::size_t at = json.size();
      append_task_json(json, t);
      chunk.line_sizes.push_back(json.size() - at);
    }
    json += ']';
    chunk.size = json.size();
    try {
      chunk.body = zlib_compress(json, kChunkLevel);
    } catch (const Error& e) {
      throw Error(file_.string() + ": " + e.what());
    }
    // sqlar's convention: a body as long as the text is the text itself.
    if (chunk.body.size() >= json.size()) chunk.body = std::move(json);
  });
  tasks.erase(tasks.begin(), tasks.begin() + static_cast<std::ptrdiff_t>(n_taken));
  return chunks;
}

void TaskDbWriter::store(std::vector<TaskChunk> chunks) {
  Open& o = *open_;
  scene_open_ = scene_open_ || !chunks.empty();
  for (const TaskChunk& c : chunks) {
    const std::int64_t chunk = o.next_chunk++;
    o.insert_chunk.bind(1, chunk).bind(2, static_cast<std::int64_t>(c.size));
    o.insert_chunk.bind_blob(3, c.body).run();
    for (std::size_t slot = 0; slot < c.rows.size(); ++slot) {
      const TaskChunk::Row& r = c.rows[slot];
      o.insert_task.bind(1, r.id).bind(2, r.scene).bind(3, std::int64_t{r.level}).bind(4, r.type);
      o.insert_task.bind(5, chunk).bind(6, static_cast<std::int64_t>(slot)).run();
    }
    if (o.jsonl.is_open()) {
      // The text is "[" + the lines joined by "," + "]".
      const std::string text = c.body.size() == c.size ? c.body : zlib_uncompress(c.body, c.size);
      std::size_t at = 1;
      for (const std::size_t n : c.line_sizes) {
        o.jsonl.write(text.data() + at, static_cast<std::streamsize>(n)) << '\n';
        at += n + 1;
      }
    }
  }
  if (o.jsonl.is_open() && !o.jsonl) throw Error(jsonl_.string() + ": write failed");
}

void TaskDbWriter::finish(const std::vector<Vote>& votes) {
  MTG_DEMAND(!scene_open_, "a scene's tasks were stored but the scene was never ended");
  Open& o = *open_;
  store::Statement meta(o.db, "INSERT INTO meta (key, value) VALUES (?, ?)");
  for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{
           {"format", kFormat},
           {"dropped", o.dropped.dump()},
           {"coverage", o.coverage.dump()},
           {"warnings", o.warnings.dump()},
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
  db_partial_.commit();
  if (jsonl_partial_) jsonl_partial_->commit();
}

void write_task_db(const fs::path& file, const std::vector<TaskSet>& sets, const std::vector<Vote>& votes,
                   const TaskOptions& options, const fs::path& jsonl) {
  TaskDbWriter writer(file, options, jsonl);
  for (const TaskSet& set : sets) writer.add(set);
  writer.finish(votes);
}

std::vector<Task> read_tasks(const fs::path& file, const std::set<int>& levels) {
  std::vector<Task> out;
  for_each_task(file, levels, [&](Task t) { out.push_back(std::move(t)); });
  std::sort(out.begin(), out.end(), [](const Task& a, const Task& b) { return a.id < b.id; });
  return out;
}

void for_each_task(const fs::path& file, const std::set<int>& levels, const std::function<void(Task)>& take) {
  // A suite stands wherever a task set does (suite.h): `mtg run --suite` runs from its copy.
  if (is_suite_file(file)) {
    for (Task& t : read_suite(file).tasks) {
      if (levels.empty() || levels.count(t.level) != 0) take(std::move(t));
    }
    return;
  }
  store::Database db(file, store::Database::Mode::kReadOnly);
  require_format(db, file);
  // In storage order, so each chunk is inflated once (a set's levels interleave in its chunks),
  // then in id order.
  store::Statement q(db, "SELECT id, level, chunk, slot FROM tasks ORDER BY chunk, slot");
  store::Statement body(db, "SELECT size, body FROM task_chunks WHERE chunk = ?");
  constexpr std::int64_t kMaxChunkBytes = 1 << 30;  // far above 64 tasks: a larger size is damage
  std::int64_t open_chunk = -1;
  nlohmann::json chunk_tasks;
  while (q.step()) {
    if (!levels.empty() && levels.count(static_cast<int>(q.column_int(1))) == 0) continue;
    const std::string id = q.column_text(0);
    const std::int64_t chunk = q.column_int(2);
    const std::int64_t slot = q.column_int(3);
    const std::string where = file.string() + ": task " + id + ": chunk " + std::to_string(chunk);
    try {
      if (chunk != open_chunk) {
        open_chunk = -1;
        body.reset();
        body.bind(1, chunk);
        if (!body.step()) throw Error("missing");
        const std::int64_t size = body.column_int(0);
        if (size <= 0 || size > kMaxChunkBytes) throw Error("implausible size " + std::to_string(size));
        const std::string stored = body.column_blob(1);
        const auto n = static_cast<std::size_t>(size);
        chunk_tasks = nlohmann::json::parse(stored.size() == n ? stored : zlib_uncompress(stored, n));
        open_chunk = chunk;
      }
      if (!chunk_tasks.is_array() || slot < 0 || static_cast<std::size_t>(slot) >= chunk_tasks.size()) {
        throw Error("no slot " + std::to_string(slot));
      }
      Task t = task_from_json(chunk_tasks[static_cast<std::size_t>(slot)]);
      if (t.id != id) throw Error("slot " + std::to_string(slot) + " holds " + t.id);
      take(std::move(t));
    } catch (const nlohmann::json::parse_error&) {
      throw Error(where + ": not JSON");
    } catch (const nlohmann::json::exception& e) {
      throw Error(where + ": a field has the wrong type (" + e.what() + ")");
    } catch (const Error& e) {
      throw Error(where + ": " + e.what());
    }
  }
}

namespace {

// A suite's counts in the shape of task_db_stats (no drops or coverage: a suite is a sample).
nlohmann::json suite_stats(const Suite& suite) {
  nlohmann::json levels = {{"1", 0}, {"2", 0}, {"3", 0}, {"4", 0}};
  nlohmann::json types = nlohmann::json::object(), scenes = nlohmann::json::object();
  for (const Task& t : suite.tasks) {
    const std::string level = std::to_string(t.level);
    levels[level] = levels[level].get<std::int64_t>() + 1;
    types[t.type] = types.value(t.type, std::int64_t{0}) + 1;
    if (!scenes.contains(t.scene)) scenes[t.scene] = {{"1", 0}, {"2", 0}, {"3", 0}, {"4", 0}, {"total", 0}};
    scenes[t.scene][level] = scenes[t.scene][level].get<std::int64_t>() + 1;
    scenes[t.scene]["total"] = scenes[t.scene]["total"].get<std::int64_t>() + 1;
  }
  nlohmann::json meta = nlohmann::json::object();
  for (const char* key : {"format", "suite_id", "config_hash", "generator_version", "seed", "scenes"}) {
    if (const auto v = suite_meta(suite, key)) meta[key] = *v;
  }
  return {{"levels", levels}, {"types", types}, {"scenes", scenes}, {"total", suite.tasks.size()},
          {"dropped", nlohmann::json::object()}, {"coverage", nlohmann::json::object()}, {"meta", meta}};
}

// One entry of the meta table of a task database, or nullopt.
std::optional<std::string> meta_value(const fs::path& file, const std::string& key) {
  if (is_suite_file(file)) return suite_meta(read_suite(file), key);
  store::Database db(file, store::Database::Mode::kReadOnly);
  require_format(db, file);
  store::Statement q(db, "SELECT value FROM meta WHERE key = ?");
  q.bind(1, key);
  if (!q.step()) return std::nullopt;
  return q.column_text(0);
}

}  // namespace

std::map<std::string, scene::DatasetFingerprint> read_dataset_fingerprints(const fs::path& file) {
  if (is_suite_file(file)) return read_suite(file).dataset;
  const auto dataset = meta_value(file, "dataset");
  if (!dataset) return {};
  try {
    return scene::fingerprints_from_json(nlohmann::json::parse(*dataset));
  } catch (const std::exception& e) {
    throw Error(file.string() + ": malformed dataset fingerprint (" + e.what() + ")");
  }
}

std::optional<std::string> read_task_set_meta(const fs::path& file, const std::string& key) {
  return meta_value(file, key);
}

nlohmann::json read_generator_config(const fs::path& file) {
  return nlohmann::json::parse(meta_value(file, "config_json").value_or("{}"), nullptr, false);
}

nlohmann::json task_db_stats(const fs::path& file) {
  if (is_suite_file(file)) return suite_stats(read_suite(file));
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
  // The Level 4 catalogue: per scene and outcome kind, its tasks and the phrasings they use.
  std::map<std::string, std::map<std::string, std::pair<std::int64_t, std::set<std::string>>>> kinds;
  if (levels["4"].get<std::int64_t>() > 0) {
    for_each_task(file, {4}, [&](Task t) {
      auto& entry = kinds[t.scene][t.type];
      entry.first += 1;
      entry.second.insert(t.template_id);
    });
  }
  nlohmann::json outcome_kinds = nlohmann::json::object();
  for (const auto& [scene, of_type] : kinds) {
    for (const auto& [type, entry] : of_type) {
      outcome_kinds[scene][type] = {{"tasks", entry.first}, {"templates", entry.second.size()}};
    }
  }
  j["outcome_kinds"] = outcome_kinds;
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
  // Breadth (coverage.h): what each scene's tasks use of its pickable items.
  j["coverage"] = nlohmann::json::object();
  if (meta.contains("coverage")) {
    const nlohmann::json recorded = nlohmann::json::parse(meta["coverage"].get<std::string>(), nullptr, false);
    if (!recorded.is_object()) throw Error(file.string() + ": meta 'coverage' is not a JSON object");
    std::map<std::string, CoverageCount> counts;
    for_each_task(file, {}, [&](Task t) { counts[t.scene].add(t); });
    for (const auto& [scene, items] : recorded.items()) j["coverage"][scene] = counts[scene].report(coverage_items_from_json(items));
    meta.erase("coverage");
  }
  // What the generator said per scene (e.g. a Level 4 kind and the precondition that stopped it).
  j["warnings"] = meta.contains("warnings") ? nlohmann::json::parse(meta["warnings"].get<std::string>(), nullptr, false)
                                            : nlohmann::json::object();
  if (!j["warnings"].is_object()) throw Error(file.string() + ": meta 'warnings' is not a JSON object");
  meta.erase("warnings");
  meta.erase("dataset");  // file hashes: read_dataset_fingerprints
  j["meta"] = meta;
  return j;
}

}  // namespace mtg::tasks
