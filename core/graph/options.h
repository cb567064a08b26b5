#pragma once
// Every knob of the scene-graph build, with the paper's constants as defaults
// (official-impl-spec §11 item 6). A scene profile (profiles/*.json) adds dataset-level choices.

#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace mtg::graph {

/// How platforms are read where a person and the release differ (docs/graph.md, "Reach" and
/// "The arrival side"). Task sets before mtg-tasks/5 were planned as the release reads them, and
/// their runs keep that (tasks::platform_rules_of_format).
enum class PlatformRules {
  /// The release: a platform inside its furniture is its whole upward surface, behind closed
  /// doors too; an empty platform's arrival side is the largest standing area.
  kWholeSurface,
  /// A platform inside its furniture is the part an arm reaches through the opening; an empty
  /// platform's arrival side is the one that sees most of its surface (a chair from its seat's
  /// side, not behind its backrest).
  kReachedAndSeen,
};
const char* to_string(PlatformRules rules);
/// @throws mtg::Error naming `what` and the word.
PlatformRules platform_rules_from_string(std::string_view name, std::string_view what);

/// What a person calls an object model.
struct Noun {
  std::string singular;  // "sponge dish"
  std::string plural;    // "" when the regular plural reads right
  bool operator==(const Noun&) const = default;
};

struct GraphOptions {
  // Surfaces (upward faces within seed_angle of +z, merged per height).
  double seed_angle_deg = 20.0;
  double surface_height_tolerance = 0.01;  // faces within this height form one surface
  double min_platform_area = 0.0025;       // m²
  double relative_platform_area = 0.2;     // of the owner's largest upward surface
  double ceiling_coverage = 0.5;           // surface above covering this share bounds clearance
  double max_platform_height = 2.0;        // higher surfaces are out of the robot's reach
  double min_platform_width = 0.05;        // narrower strips (door tops, rims) hold nothing

  // Support tree.
  double contact_tolerance = 0.05;   // parent rule: surface within ±5 cm of the object's bottom
  double min_support_overlap = 0.4;  // share of min(footprint, platform) area that must overlap
  double max_settle_drop = 0.3;      // beyond ±5 cm, drop at most this far (with a warning)
  double floor_covering_height = 0.03;  // flat, large floor objects (rugs) are part of the floor
  double floor_covering_min_area = 0.25;  // m²
  double min_furniture_height = 0.2;    // lower movable floor objects are items on the floor

  // Free space.
  double min_region_size = 0.03;     // free-space regions narrower than this are not numbered

  // Standing areas and visibility.
  double robot_size = 0.4;           // square robot footprint, m
  double standing_depth = 0.5;       // strip depth outside the owner's side, m
  double raster_resolution = 0.01;   // m per cell
  // Light furniture a person steps around or pushes aside (a stool, a dining chair): movable,
  // at most this footprint and height. It does not take standing area away, but a standing
  // point clear of it is preferred (docs/graph.md, "Standing areas").
  double steppable_max_area = 0.36;  // m²
  double steppable_max_height = 1.0; // m
  // Observer heights above the surface for the visibility rays (visible from any of them).
  std::vector<double> camera_heights_above = {0.15, 0.35, 0.6};
  PlatformRules platform_rules = PlatformRules::kReachedAndSeen;

  // Scene profile: templates dropped before anything else (dataset-level, not per apartment).
  std::set<std::string> exclude_templates;
  // Scene profile: the words a person uses for each template's model ("sponge dish"), and their
  // plural where English does not add -s/-es ("pairs of shoes"). Templates without one are
  // called by their dataset class.
  std::map<std::string, Noun> nouns;
  // Scene profile: words a person uses for several nouns ("cup" for mugs and teacups too): told
  // the word, a person considers each of them (a look-alike, a member of "every cup").
  std::map<std::string, std::set<std::string>> noun_covers;
  std::string profile_name = "none";

  /// Canonical JSON of every field (for hashing into task sets and for graph.json).
  nlohmann::json to_json() const;
  nlohmann::json nouns_json() const;
};

/// Loads a profile: "none", a built-in name ("replica_cad"), or a path to a JSON file with
/// {"exclude_templates": [...], "nouns": {"<template>": "<noun>" | {"noun": ..., "plural": ...}}}.
/// @throws mtg::Error naming the profile, file and field.
void apply_profile(GraphOptions& options, const std::string& profile);

/// The built-in default profile name.
inline constexpr const char* kDefaultProfile = "replica_cad";

}  // namespace mtg::graph
