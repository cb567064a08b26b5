#include "core/tasks/draw.h"

#include <algorithm>
#include <cctype>
#include <set>

#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/rng.h"

namespace mtg::tasks {

DrawKind draw_kind_from_string(const std::string& name) {
  if (name == "stratified") return DrawKind::kStratified;
  if (name == "uniform") return DrawKind::kUniform;
  throw Error("a draw is stratified or uniform, not '" + name + "'");
}

const char* to_string(DrawKind kind) { return kind == DrawKind::kStratified ? "stratified" : "uniform"; }

namespace {

// "frl_apartment_cup_01_3" -> "frl_apartment_cup_01": instances of one model share a stratum.
std::string model_of(const std::string& object) {
  const auto cut = object.find_last_of('_');
  if (cut == std::string::npos || cut + 1 == object.size()) return object;
  const bool index = std::all_of(object.begin() + static_cast<std::ptrdiff_t>(cut) + 1, object.end(),
                                 [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
  return index ? object.substr(0, cut) : object;
}

std::string outcome_kind(const Task& t) {
  const auto colon = t.type.find(':');
  return colon == std::string::npos ? t.type : t.type.substr(colon + 1);
}

}  // namespace

Stratum stratum_of(const Task& t) {
  if (t.level == 4) return {outcome_kind(t), t.template_id};
  if (t.level == 3) {
    std::string first = t.source;
    std::set<std::string> others;
    if (t.goal.is_object() && t.goal.contains("sequence") && t.goal["sequence"].is_array()) {
      bool first_part = true;
      for (const auto& part : t.goal["sequence"]) {
        const std::string source = part.value("source", std::string());
        const std::string platform = part.value("platform", std::string());
        if (first_part && !source.empty()) first = source;
        if (!first_part && !source.empty()) others.insert(source);
        if (!platform.empty()) others.insert(platform);
        first_part = false;
      }
    }
    std::string rest;
    for (const auto& p : others) rest += (rest.empty() ? "" : "+") + p;
    return {first, rest};
  }
  return {t.source, model_of(t.item)};
}

const char* stratum_name(int level) { return level == 4 ? "outcome kind" : "source platform"; }

std::uint64_t draw_seed(std::uint64_t seed, const std::string& scene, int level) {
  return derive_seed(seed, fnv1a64(scene + "/L" + std::to_string(level)));
}

std::vector<const Task*> draw_tasks(std::vector<const Task*> group, int n, DrawKind kind, std::uint64_t seed) {
  const auto by_id = [](const Task* a, const Task* b) { return a->id < b->id; };
  std::sort(group.begin(), group.end(), by_id);
  if (n <= 0 || static_cast<int>(group.size()) <= n) return group;
  Rng rng(seed);
  if (kind == DrawKind::kUniform) {
    // Today's draw as it was (plans made before stratification say "uniform" and mean this).
    rng.shuffle(group);
    group.resize(static_cast<std::size_t>(n));
    std::sort(group.begin(), group.end(), by_id);
    return group;
  }
  // Cells in key order, then each list shuffled: the deal depends on the seed and the tasks only.
  std::map<std::string, std::map<std::string, std::vector<const Task*>>> cells;
  for (const Task* t : group) {
    Stratum s = stratum_of(*t);
    cells[s.primary][s.secondary].push_back(t);
  }
  struct Primary {
    std::vector<std::vector<const Task*>> cells;  // each shuffled, taken from the back
    std::size_t cursor = 0;
  };
  std::vector<Primary> primaries;
  for (auto& [name, secondaries] : cells) {
    Primary p;
    for (auto& [sub, tasks] : secondaries) {
      rng.shuffle(tasks);
      p.cells.push_back(std::move(tasks));
    }
    rng.shuffle(p.cells);
    primaries.push_back(std::move(p));
  }
  rng.shuffle(primaries);
  std::vector<const Task*> chosen;
  chosen.reserve(static_cast<std::size_t>(n));
  while (static_cast<int>(chosen.size()) < n) {
    bool took = false;
    for (Primary& p : primaries) {
      if (static_cast<int>(chosen.size()) == n) break;
      // This primary's next cell that still has a task, round-robin.
      for (std::size_t tried = 0; tried < p.cells.size(); ++tried) {
        auto& cell = p.cells[p.cursor];
        p.cursor = (p.cursor + 1) % p.cells.size();
        if (cell.empty()) continue;
        chosen.push_back(cell.back());
        cell.pop_back();
        took = true;
        break;
      }
    }
    if (!took) break;  // cannot happen while n < group size; a guard against an endless loop
  }
  std::sort(chosen.begin(), chosen.end(), by_id);
  return chosen;
}

std::map<int, LevelSpread> spread_of(const std::vector<const Task*>& tasks) {
  // Per level and scene: a platform belongs to one scene, so its share is of that scene's tasks.
  std::map<int, std::map<std::string, std::map<std::string, std::int64_t>>> counts;
  for (const Task* t : tasks) ++counts[t->level][t->scene][stratum_of(*t).primary];
  std::map<int, LevelSpread> out;
  for (const auto& [level, scenes] : counts) {
    LevelSpread worst;
    worst.level = level;
    for (const auto& [scene, strata] : scenes) {
      LevelSpread s;
      s.level = level;
      s.strata = static_cast<std::int64_t>(strata.size());
      for (const auto& [name, n] : strata) {
        s.tasks += n;
        if (n > s.biggest_tasks) {
          s.biggest = scene + "/" + name;
          s.biggest_tasks = n;
        }
      }
      if (worst.tasks == 0 || s.biggest_share() > worst.biggest_share()) worst = s;
    }
    out.emplace(level, worst);
  }
  return out;
}

nlohmann::json to_json(const std::map<int, LevelSpread>& spread) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [level, s] : spread) {
    j[std::to_string(level)] = {{"stratum", stratum_name(level)}, {"tasks", s.tasks}, {"strata", s.strata},
                                {"biggest", s.biggest}, {"biggest_tasks", s.biggest_tasks},
                                {"biggest_share", s.biggest_share()}};
  }
  return j;
}

}  // namespace mtg::tasks
