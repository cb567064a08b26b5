#include "core/tasks/task.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <string_view>

#include "core/util/error.h"
#include "core/util/json_file.h"
#include "core/util/hash.h"

namespace mtg::tasks {

Ambiguity ambiguity_from_string(const std::string& name) {
  if (name == "name") return Ambiguity::kNameWithoutId;
  if (name == "category") return Ambiguity::kCategory;
  if (name == "noun") return Ambiguity::kNoun;
  throw Error("unknown ambiguity rule '" + name + "' (use noun, category or name)");
}

const char* to_string(Ambiguity a) {
  switch (a) {
    case Ambiguity::kNameWithoutId: return "name";
    case Ambiguity::kCategory: return "category";
    case Ambiguity::kNoun: return "noun";
  }
  return "noun";
}

nlohmann::json to_json(const Identification& id) {
  return {{"part", id.part},           {"role", id.role},         {"object", id.object},
          {"platform", id.platform},   {"reference", id.reference.to_json()}, {"phrase", id.phrase}};
}

Identification identification_from_json(const nlohmann::json& j) {
  for (const char* key : {"part", "role", "object", "platform", "reference", "phrase"}) {
    if (!j.contains(key)) throw Error(std::string("identification: missing field '") + key + "'");
  }
  Identification id;
  id.part = json_integer<int>(j["part"], "identification part");
  id.role = j["role"].get<std::string>();
  id.object = j["object"].get<std::string>();
  id.platform = j["platform"].get<std::string>();
  id.reference = Reference::from_json(j["reference"]);
  id.phrase = j["phrase"].get<std::string>();
  return id;
}

nlohmann::json to_json(const OraclePlacement& p) {
  return {{"part", p.part},
          {"object", p.object},
          {"platform", p.platform},
          {"x", p.position.x()},
          {"y", p.position.y()},
          {"z", p.position.z()},
          // A surface goal holds wherever the item stands: an unbounded margin, null in JSON.
          {"margin", std::isfinite(p.margin) ? nlohmann::json(p.margin) : nlohmann::json(nullptr)}};
}

OraclePlacement oracle_placement_from_json(const nlohmann::json& j) {
  for (const char* key : {"part", "object", "platform", "x", "y", "z", "margin"}) {
    if (!j.contains(key)) throw Error(std::string("oracle placement: missing field '") + key + "'");
  }
  OraclePlacement p;
  p.part = json_integer<int>(j["part"], "oracle placement part");
  p.object = j["object"].get<std::string>();
  p.platform = j["platform"].get<std::string>();
  p.position = {j["x"].get<double>(), j["y"].get<double>(), j["z"].get<double>()};
  p.margin = j["margin"].is_null() ? std::numeric_limits<double>::infinity() : j["margin"].get<double>();
  return p;
}

namespace {

template <class Record>
nlohmann::json array_of(const std::vector<Record>& records) {
  nlohmann::json j = nlohmann::json::array();
  for (const Record& r : records) j.push_back(to_json(r));
  return j;
}

template <class Record>
std::vector<Record> records_of(const nlohmann::json& j, Record (*read)(const nlohmann::json&)) {
  std::vector<Record> out;
  for (const auto& item : j) out.push_back(read(item));
  return out;
}

}  // namespace

nlohmann::json to_json(const std::vector<Identification>& ids) { return array_of(ids); }
std::vector<Identification> identifications_from_json(const nlohmann::json& j) {
  return records_of(j, &identification_from_json);
}
nlohmann::json to_json(const std::vector<OraclePlacement>& placements) { return array_of(placements); }
std::vector<OraclePlacement> oracle_placements_from_json(const nlohmann::json& j) {
  return records_of(j, &oracle_placement_from_json);
}

void DropCounts::merge(const DropCounts& other) {
  for (const auto& [reason, levels] : other.by_reason) {
    for (const auto& [level, n] : levels) add(reason, level, n);
  }
}

nlohmann::json DropCounts::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [reason, levels] : by_reason) {
    for (const auto& [level, n] : levels) j[reason][std::to_string(level)] = n;
  }
  return j;
}

namespace {

// N of "mtg-tasks/N"; 0 for anything else (a set that does not say is of the oldest format).
int format_version(const std::string& format) {
  static constexpr std::string_view kPrefix = "mtg-tasks/";
  if (format.rfind(kPrefix, 0) != 0) return 0;
  int version = 0;
  const char* first = format.data() + kPrefix.size();
  const char* last = format.data() + format.size();
  const auto [end, error] = std::from_chars(first, last, version);
  return error == std::errc{} && end == last ? version : 0;
}

}  // namespace

episode::Numbering numbering_of_format(const std::string& format) {
  return format_version(format) >= 4 ? episode::Numbering::kStable : episode::Numbering::kPerState;
}

graph::PlatformRules platform_rules_of_format(const std::string& format) {
  return format_version(format) >= 5 ? graph::PlatformRules::kReachedAndSeen : graph::PlatformRules::kWholeSurface;
}

nlohmann::json TaskOptions::to_json() const {
  return {{"generator", kGeneratorVersion},
          {"levels", levels},
          {"ambiguity", tasks::to_string(ambiguity)},
          {"level3_count", level3_count},
          {"level3_chain", level3_chain},
          {"level4_max_moves", level4_max_moves},
          {"level4_max_kind_share", level4_max_kind_share},
          {"level4_templates", level4_templates},
          {"step_limit", rules.step_limit},
          {"min_region_size", rules.min_region_size},
          {"min_margin", min_margin},
          {"min_goal_area", min_goal_area},
          {"around_distance", goals.around_distance},
          {"visibility", visibility ? visibility->to_json() : nlohmann::json()}};
}

std::string TaskOptions::config_hash() const { return to_hex(fnv1a64(to_json().dump())); }

}  // namespace mtg::tasks
