#include "core/tasks/coverage.h"

#include <algorithm>

#include "core/tasks/referring.h"
#include "core/util/error.h"

namespace mtg::tasks {

std::vector<CoverageItem> coverage_items(const graph::SceneGraph& g, const episode::WorldState& s, Ambiguity rule,
                                         const render::VisibilityOracle* seeing) {
  std::vector<CoverageItem> out;
  for (const graph::PlatformId p : g.navigable) {
    const std::vector<graph::ObjectId> items = episode::pickable_on(g, s, p);
    if (items.empty()) continue;
    const std::shared_ptr<const render::ViewSight> sight = seeing != nullptr ? seeing->arrival_view(s, p) : nullptr;
    for (const graph::ObjectId o : items) {
      CoverageItem c;
      c.object = g.objects[o].name;
      c.platform = g.platforms[p].name;
      c.noun = noun_of(g.objects[o], rule);
      c.seen = sight == nullptr || sight->clearly_visible(o);
      c.lookalike = has_lookalike(g, s, o, p, rule);
      out.push_back(std::move(c));
    }
  }
  return out;
}

nlohmann::json to_json(const std::vector<CoverageItem>& items) {
  nlohmann::json out = nlohmann::json::array();
  for (const CoverageItem& c : items) {
    out.push_back({{"object", c.object}, {"platform", c.platform}, {"noun", c.noun}, {"seen", c.seen},
                   {"lookalike", c.lookalike}});
  }
  return out;
}

std::vector<CoverageItem> coverage_items_from_json(const nlohmann::json& j) {
  std::vector<CoverageItem> out;
  try {
    for (const nlohmann::json& e : j) {
      out.push_back({e.at("object").get<std::string>(), e.at("platform").get<std::string>(),
                     e.at("noun").get<std::string>(), e.at("seen").get<bool>(), e.at("lookalike").get<bool>()});
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("coverage: malformed item (") + e.what() + ")");
  }
  return out;
}

namespace {

// The items an atomic goal or a Level 3 part moves, and its source platform.
void atomic_parts(const nlohmann::json& goal, std::vector<std::pair<std::string, std::string>>& out) {
  auto part = [&](const nlohmann::json& a) { out.emplace_back(a.value("item", ""), a.value("source", "")); };
  if (goal.contains("atomic")) part(goal["atomic"]);
  if (goal.contains("sequence")) {
    for (const nlohmann::json& a : goal["sequence"]) part(a);
  }
}

}  // namespace

void CoverageCount::add(const Task& task) {
  std::vector<std::pair<std::string, std::string>> parts;
  atomic_parts(task.goal, parts);
  for (const auto& [item, source] : parts) {
    in_any_.insert(item);
    if (task.level == 1 || task.level == 2) {
      in_levels_1_2_.insert(item);
      sources_1_2_.insert(source);
    }
    if (task.level == 2) {
      in_level_2_.insert(item);
      ++level_2_sources_[source];
      ++level_2_;
    }
  }
  if (task.goal.contains("outcome")) {
    for (const nlohmann::json& p : task.goal["outcome"].value("all", nlohmann::json::array())) {
      for (const char* list : {"objects", "objects2"}) {
        for (const nlohmann::json& o : p.value(list, nlohmann::json::array())) in_any_.insert(o.get<std::string>());
      }
    }
  }
  if (task.level == 1 || task.level == 2) {
    for (const Identification& id : task.identify) phrases_1_2_.insert(id.phrase);
  }
}

nlohmann::json CoverageCount::report(const std::vector<CoverageItem>& items) const {
  long l12 = 0, any = 0, seen_alike = 0, seen_alike_l2 = 0;
  std::set<std::string> nouns;
  nlohmann::json missing = nlohmann::json::array(), missing_l2 = nlohmann::json::array();
  for (const CoverageItem& c : items) {
    const bool used = in_levels_1_2_.count(c.object) != 0;
    l12 += used ? 1 : 0;
    any += in_any_.count(c.object) != 0 ? 1 : 0;
    if (used) nouns.insert(c.noun);
    if (!used) missing.push_back(c.object);
    if (c.seen && c.lookalike) {
      ++seen_alike;
      if (in_level_2_.count(c.object) != 0) {
        ++seen_alike_l2;
      } else {
        missing_l2.push_back(c.object);
      }
    }
  }
  std::vector<long> sizes;
  for (const auto& [source, n] : level_2_sources_) sizes.push_back(n);
  std::sort(sizes.rbegin(), sizes.rend());
  long top3 = 0;
  for (std::size_t k = 0; k < sizes.size() && k < 3; ++k) top3 += sizes[k];
  const auto share = [](long a, long b) { return b > 0 ? static_cast<double>(a) / static_cast<double>(b) : 0.0; };
  return {{"pickable", items.size()},
          {"in_levels_1_2", l12},
          {"in_any_task", any},
          {"share_in_levels_1_2", share(l12, static_cast<long>(items.size()))},
          {"seen_with_lookalike", seen_alike},
          {"seen_with_lookalike_in_level_2", seen_alike_l2},
          {"level_2_top3_share", share(top3, level_2_)},
          {"source_platforms_1_2", sources_1_2_.size()},
          {"nouns_1_2", nouns.size()},
          {"phrases_1_2", phrases_1_2_.size()},
          {"not_in_levels_1_2", missing},
          {"seen_lookalikes_not_in_level_2", missing_l2}};
}

}  // namespace mtg::tasks
