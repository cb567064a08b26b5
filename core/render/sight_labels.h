#pragma once
// Calibrating "clearly visible" (visibility.h) against people's eyes: objects drawn from the
// views of a scene, each shown to a person with an arrow pointing at it ("what is there?"), and
// the person's answers as labels. The rule's thresholds are then checked against the labels
// (docs/render.md, "Calibrated by eye"). Pure: the views' pixels come from the id pass.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/render/camera.h"
#include "core/render/visibility_options.h"

namespace mtg::render {

/// One object in one view, as a person was asked about it.
struct SightCase {
  std::string id;        // "s001"
  std::string scene;
  std::string platform;  // the platform the view is of
  int side = 0;
  std::string object;    // graph object name
  std::string noun;      // what the noun table calls it (not shown to the person)
  Camera camera;         // the view, at the agent's image size
  double visible_pixels = 0.0;     // image pixels showing the object (pass pixels x scale^2)
  double silhouette_pixels = 0.0;  // image pixels it would cover alone
  Eigen::Vector2d arrow_tip = Eigen::Vector2d::Zero();  // image pixels the arrow points at

  double share() const { return silhouette_pixels > 0.0 ? visible_pixels / silhouette_pixels : 0.0; }
};

/// A person's answer about one case.
struct SightAnswer {
  std::string id;
  std::string rater;
  bool seen = false;    // "I can see an object there clearly enough to say what it is"
  std::string name;     // what they call it ("" when not seen)
  bool named = false;   // the name fits the object (judged against the noun and its synonyms)
  /// The label: the person saw the object meant, and named it.
  bool label() const { return seen && named; }
};

nlohmann::json to_json(const SightCase& c);
SightCase sight_case_from_json(const nlohmann::json& j);
nlohmann::json to_json(const SightAnswer& a);
/// @throws mtg::Error naming the field.
SightAnswer sight_answer_from_json(const nlohmann::json& j);

/// What the rule says of a case.
bool clearly_visible(const SightCase& c, const VisibilityOptions& rule);

/// Agreement of the rule with the labels.
struct Confusion {
  int both_seen = 0;        // rule: visible, person: seen
  int rule_only = 0;        // rule: visible, person: not
  int person_only = 0;      // rule: not, person: seen
  int neither = 0;
  int total() const { return both_seen + rule_only + person_only + neither; }
  double agreement() const { return total() > 0 ? static_cast<double>(both_seen + neither) / total() : 0.0; }
};

/// `labels[i]` is the label of `cases[i]`.
Confusion confusion(const std::vector<SightCase>& cases, const std::vector<bool>& labels, const VisibilityOptions& rule);

/// The thresholds (min_pixels, min_share) of a grid that agree best with the labels; ties go to the
/// stricter rule (more pixels, then a larger share), so a task never names what people missed
/// for the sake of a tie.
VisibilityOptions best_thresholds(const std::vector<SightCase>& cases, const std::vector<bool>& labels,
                                  VisibilityOptions base);

/// Indices of up to `count` of `cases`, drawn with `seed` evenly over cells of visible pixels and
/// share (so the cases near the rule's edges are as many as the plain ones).
std::vector<std::size_t> stratified_draw(const std::vector<SightCase>& cases, std::size_t count, std::uint64_t seed);

}  // namespace mtg::render
