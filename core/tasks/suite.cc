#include "core/tasks/suite.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include "core/tasks/task_db.h"
#include "core/util/atomic_file.h"
#include "core/util/build_info.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "core/util/sha256.h"

namespace mtg::tasks {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kIdDigits = 12;

nlohmann::json draw_json(const SuiteDraw& d) {
  return {{"per_level", d.per_level}, {"seed", d.seed},     {"kind", to_string(d.kind)},
          {"levels", d.levels},       {"scenes", d.scenes}, {"sizing", d.sizing}};
}

SuiteDraw draw_from_json(const nlohmann::json& j) {
  SuiteDraw d;
  d.per_level = json_integer<int>(j.at("per_level"), "draw per_level");
  d.seed = json_integer<std::uint64_t>(j.at("seed"), "draw seed");
  d.kind = draw_kind_from_string(j.at("kind").get<std::string>());
  if (!j.at("levels").is_array()) throw Error("draw levels: not an array");
  for (const auto& level : j.at("levels")) d.levels.insert(json_integer<int>(level, "draw level"));
  d.scenes = j.at("scenes").get<std::set<std::string>>();
  d.sizing = j.value("sizing", nlohmann::json(nullptr));
  return d;
}

bool plain_name(const std::string& name) {
  return !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '_' || c == '-';
         });
}

std::vector<const Task*> pointers(const std::vector<Task>& tasks) {
  std::vector<const Task*> out;
  out.reserve(tasks.size());
  for (const Task& t : tasks) out.push_back(&t);
  return out;
}

}  // namespace

Suite draw_suite(std::string name, const std::vector<Task>& tasks, SuiteDraw draw, nlohmann::json generator,
                 const std::map<std::string, scene::DatasetFingerprint>& dataset) {
  if (draw.per_level < 1) throw Error("tasks per level must be at least 1, not " + std::to_string(draw.per_level));
  std::map<std::pair<std::string, int>, std::vector<const Task*>> groups;
  std::set<std::string> scenes_seen;
  for (const Task& t : tasks) {
    scenes_seen.insert(t.scene);
    if ((draw.scenes.empty() || draw.scenes.count(t.scene) != 0) && draw.levels.count(t.level) != 0) {
      groups[{t.scene, t.level}].push_back(&t);
    }
  }
  for (const std::string& scene : draw.scenes) {
    if (scenes_seen.count(scene) == 0) throw Error("the task set has no task of scene " + scene);
  }
  if (groups.empty()) throw Error("the task set has no task of the scenes and levels asked for");
  Suite s;
  s.name = std::move(name);
  s.generator = std::move(generator);
  for (auto& [key, group] : groups) {
    for (const Task* t : draw_tasks(std::move(group), draw.per_level, draw.kind, draw_seed(draw.seed, key.first, key.second))) {
      s.tasks.push_back(*t);
    }
    const auto f = dataset.find(key.first);
    if (f == dataset.end()) throw Error("the task set holds no dataset fingerprint of scene " + key.first);
    s.dataset[key.first] = f->second;
  }
  if (draw.scenes.empty()) {
    for (const auto& [key, group] : groups) draw.scenes.insert(key.first);
  }
  s.draw = std::move(draw);
  std::sort(s.tasks.begin(), s.tasks.end(), [](const Task& a, const Task& b) { return a.id < b.id; });
  return s;
}

nlohmann::json suite_spread(const Suite& s) { return to_json(spread_of(pointers(s.tasks))); }

std::string Suite::id() const { return name + "@" + digest.substr(0, kIdDigits); }

nlohmann::json suite_content(const Suite& s) {
  nlohmann::json tasks = nlohmann::json::array();
  for (const Task& t : s.tasks) tasks.push_back(task_to_json(t));
  return {{"name", s.name},
          {"license", s.license},
          {"generator", s.generator},
          {"draw", draw_json(s.draw)},
          {"spread", suite_spread(s)},
          {"dataset", scene::to_json(s.dataset)},
          {"tasks", std::move(tasks)}};
}

std::string suite_digest(const Suite& s) { return sha256_hex(suite_content(s).dump()); }

void write_suite(const fs::path& file, Suite& s) {
  if (!plain_name(s.name)) {
    throw Error("suite name '" + s.name + "': use letters, digits, '.', '_' and '-' (at most 64), e.g. standard-replicacad");
  }
  std::sort(s.tasks.begin(), s.tasks.end(), [](const Task& a, const Task& b) { return a.id < b.id; });
  const nlohmann::json content = suite_content(s);
  s.digest = sha256_hex(content.dump());
  s.made_with = {{"mtg_version", mtg_version()}, {"git_revision", mtg_git_revision()}};
  // Readable and diffable: one line per top-level field and per task.
  write_file_atomically(file, [&](std::ostream& out) {
    out << "{\"format\": " << nlohmann::json(kSuiteFormat).dump() << ",\n"
        << "\"id\": " << nlohmann::json(s.id()).dump() << ",\n"
        << "\"digest\": " << nlohmann::json(s.digest).dump() << ",\n"
        << "\"made_with\": " << s.made_with.dump() << ",\n"
        << "\"content\": {\n";
    bool first = true;
    for (const auto& [key, value] : content.items()) {
      if (key == "tasks") continue;
      out << (first ? "" : ",\n") << nlohmann::json(key).dump() << ": " << value.dump();
      first = false;
    }
    out << ",\n\"tasks\": [\n";
    const auto& tasks = content["tasks"];
    for (std::size_t i = 0; i < tasks.size(); ++i) out << tasks[i].dump() << (i + 1 < tasks.size() ? ",\n" : "\n");
    out << "]}}\n";
  });
}

Suite read_suite(const fs::path& file) {
  const std::string where = file.string();
  std::error_code ec;
  if (const auto bytes = fs::file_size(file, ec); !ec && bytes > kMaxSuiteBytes) {
    throw Error(where + ": " + std::to_string(bytes >> 20) + " MiB is more than a suite may hold (" +
                std::to_string(kMaxSuiteBytes >> 20) + " MiB)");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(where + ": cannot read the suite (" + (fs::exists(file) ? "not readable" : "no such file") + ")");
  std::ostringstream text;
  text << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(where + ": not a whole suite file (not JSON, or cut short: byte " + std::to_string(e.byte) + ")");
  } catch (const nlohmann::json::exception& e) {
    // A number too large for a double (out_of_range.406), found by scripts/fuzz.
    throw Error(where + ": not a suite file (" + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("format")) throw Error(where + ": not a suite (no \"format\")");
  if (!j["format"].is_string() || j["format"].get<std::string>() != kSuiteFormat) {
    throw Error(where + ": suite format " + j["format"].dump() + " is not one this mtg reads (" + kSuiteFormat +
                "); a newer mtg made it");
  }
  Suite s;
  try {
    const nlohmann::json& c = j.at("content");
    s.digest = j.at("digest").get<std::string>();
    const std::string actual = sha256_hex(c.dump());
    if (actual != s.digest) {
      throw Error("its content does not match its digest (edited or damaged): the file says " + s.digest.substr(0, kIdDigits) +
                  "…, the content hashes to " + actual.substr(0, kIdDigits) + "…");
    }
    s.made_with = j.value("made_with", nlohmann::json::object());
    s.name = c.at("name").get<std::string>();
    s.license = c.at("license").get<std::string>();
    s.generator = c.at("generator");
    s.draw = draw_from_json(c.at("draw"));
    s.dataset = scene::fingerprints_from_json(c.at("dataset"));
    for (const auto& t : c.at("tasks")) s.tasks.push_back(task_from_json(t));
    if (j.at("id").get<std::string>() != s.id()) {
      throw Error("its id " + j["id"].dump() + " is not its name and digest (" + s.id() + ")");
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": malformed suite (" + e.what() + ")");
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
  for (std::size_t i = 0; i < s.tasks.size(); ++i) {
    const Task& t = s.tasks[i];
    if (i > 0 && !(s.tasks[i - 1].id < t.id)) throw Error(where + ": task " + t.id + " is repeated or out of order");
    if (s.dataset.count(t.scene) == 0) throw Error(where + ": task " + t.id + ": scene " + t.scene + " has no dataset fingerprint");
  }
  if (s.tasks.empty()) throw Error(where + ": the suite holds no task");
  return s;
}

bool is_suite_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  char c = 0;
  while (in.get(c)) {
    if (std::isspace(static_cast<unsigned char>(c)) == 0) return c == '{';
  }
  return false;
}

std::optional<std::string> suite_meta(const Suite& s, const std::string& key) {
  if (key == "format") return std::string(kSuiteFormat);
  if (key == "suite_id") return s.id();
  if (key == "dataset") return scene::to_json(s.dataset).dump();
  if (key == "config_json" && s.generator.contains("config")) return s.generator["config"].dump();
  if (key == "config_hash" && s.generator.contains("config_hash")) return s.generator["config_hash"].get<std::string>();
  if (key == "generator_version" && s.generator.contains("task_format")) return s.generator["task_format"].get<std::string>();
  if (key == "seed" && s.generator.contains("seed")) return s.generator["seed"].get<std::string>();
  if (key == "scenes") {
    std::string scenes;
    for (const auto& [scene, f] : s.dataset) scenes += (scenes.empty() ? "" : ",") + scene;
    return scenes;
  }
  return std::nullopt;
}

}  // namespace mtg::tasks
