#include "core/graph/options.h"

#include <filesystem>

#include "core/graph/profiles_embedded.h"
#include "core/util/error.h"
#include "core/util/json_file.h"

namespace mtg::graph {

const char* to_string(PlatformRules rules) {
  return rules == PlatformRules::kWholeSurface ? "whole_surface" : "reached_and_seen";
}

PlatformRules platform_rules_from_string(std::string_view name, std::string_view what) {
  if (name == "whole_surface") return PlatformRules::kWholeSurface;
  if (name == "reached_and_seen") return PlatformRules::kReachedAndSeen;
  throw Error(std::string(what) + ": unknown platform rules '" + std::string(name) +
              "' (use reached_and_seen or whole_surface)");
}

nlohmann::json GraphOptions::nouns_json() const {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [name, noun] : nouns) {
    out[name] = noun.plural.empty() ? nlohmann::json(noun.singular)
                                    : nlohmann::json{{"noun", noun.singular}, {"plural", noun.plural}};
  }
  return out;
}

nlohmann::json GraphOptions::to_json() const {
  return {{"seed_angle_deg", seed_angle_deg},
          {"surface_height_tolerance", surface_height_tolerance},
          {"min_platform_area", min_platform_area},
          {"relative_platform_area", relative_platform_area},
          {"ceiling_coverage", ceiling_coverage},
          {"max_platform_height", max_platform_height},
          {"min_platform_width", min_platform_width},
          {"contact_tolerance", contact_tolerance},
          {"min_support_overlap", min_support_overlap},
          {"max_settle_drop", max_settle_drop},
          {"floor_covering_height", floor_covering_height},
          {"floor_covering_min_area", floor_covering_min_area},
          {"min_furniture_height", min_furniture_height},
          {"min_region_size", min_region_size},
          {"robot_size", robot_size},
          {"standing_depth", standing_depth},
          {"steppable_max_area", steppable_max_area},
          {"steppable_max_height", steppable_max_height},
          {"raster_resolution", raster_resolution},
          {"camera_heights_above", camera_heights_above},
          {"platform_rules", to_string(platform_rules)},
          {"profile", profile_name},
          {"exclude_templates", exclude_templates},
          {"nouns", nouns_json()},
          {"noun_covers", noun_covers}};
}

void apply_profile(GraphOptions& options, const std::string& profile) {
  options.exclude_templates.clear();
  options.nouns.clear();
  options.noun_covers.clear();
  options.profile_name = profile;
  if (profile == "none" || profile.empty()) return;
  nlohmann::json doc;
  std::string source;
  if (profile == "replica_cad") {
    doc = nlohmann::json::parse(kReplicaCadProfileJson);
    source = "built-in profile replica_cad";
  } else if (std::filesystem::exists(profile)) {
    doc = read_json_file(profile);
    source = profile;
  } else {
    throw Error("unknown scene profile '" + profile +
                "' (use none, replica_cad, or a path to a profile JSON file)");
  }
  const JsonField root(doc, source);
  if (auto list = root.find("exclude_templates")) {
    for (std::size_t i = 0; i < list->size(); ++i) {
      options.exclude_templates.insert(list->at(i).as_string());
    }
  }
  if (auto nouns = root.find("nouns")) {
    for (const std::string& name : nouns->keys()) {
      const JsonField entry = nouns->at(name);
      Noun noun;
      if (entry.is_object()) {
        noun.singular = entry.at("noun").as_string();
        if (auto plural = entry.find("plural")) noun.plural = plural->as_string();
      } else {
        noun.singular = entry.as_string();
      }
      if (noun.singular.empty()) entry.fail("a noun must not be empty");
      options.nouns[name] = std::move(noun);
    }
  }
  if (auto covers = root.find("covers")) {
    for (const std::string& word : covers->keys()) {
      const JsonField list = covers->at(word);
      for (std::size_t i = 0; i < list.size(); ++i) options.noun_covers[word].insert(list.at(i).as_string());
    }
  }
}

}  // namespace mtg::graph
