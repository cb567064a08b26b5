#include "core/render/sight_labels.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/util/error.h"
#include "core/util/rng.h"

namespace mtg::render {
namespace {

nlohmann::json camera_json(const Camera& c) {
  const Eigen::Quaterniond q(c.X_WC.linear());
  const Eigen::Vector3d t = c.X_WC.translation();
  return {{"eye", {t.x(), t.y(), t.z()}}, {"rotation_wxyz", {q.w(), q.x(), q.y(), q.z()}}, {"fovy", c.fovy},
          {"width", c.width}, {"height", c.height}, {"near", c.near}, {"far", c.far}};
}

Camera camera_from_json(const nlohmann::json& j) {
  Camera c;
  const auto& e = j.at("eye");
  const auto& r = j.at("rotation_wxyz");
  c.X_WC = Eigen::Isometry3d::Identity();
  c.X_WC.linear() = Eigen::Quaterniond(r.at(0).get<double>(), r.at(1).get<double>(), r.at(2).get<double>(),
                                       r.at(3).get<double>())
                        .normalized()
                        .toRotationMatrix();
  c.X_WC.translation() = Eigen::Vector3d(e.at(0).get<double>(), e.at(1).get<double>(), e.at(2).get<double>());
  c.fovy = j.at("fovy").get<double>();
  c.width = j.at("width").get<int>();
  c.height = j.at("height").get<int>();
  c.near = j.at("near").get<double>();
  c.far = j.at("far").get<double>();
  return c;
}

template <class F>
auto field(const nlohmann::json& j, const char* name, F get) {
  try {
    return get(j.at(name));
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("sight label: field '") + name + "': " + e.what());
  }
}

}  // namespace

nlohmann::json to_json(const SightCase& c) {
  return {{"id", c.id}, {"scene", c.scene}, {"platform", c.platform}, {"side", c.side}, {"object", c.object},
          {"noun", c.noun}, {"camera", camera_json(c.camera)}, {"visible_pixels", c.visible_pixels},
          {"silhouette_pixels", c.silhouette_pixels}, {"arrow_tip", {c.arrow_tip.x(), c.arrow_tip.y()}}};
}

SightCase sight_case_from_json(const nlohmann::json& j) {
  SightCase c;
  c.id = field(j, "id", [](const auto& v) { return v.template get<std::string>(); });
  c.scene = field(j, "scene", [](const auto& v) { return v.template get<std::string>(); });
  c.platform = field(j, "platform", [](const auto& v) { return v.template get<std::string>(); });
  c.side = field(j, "side", [](const auto& v) { return v.template get<int>(); });
  c.object = field(j, "object", [](const auto& v) { return v.template get<std::string>(); });
  c.noun = field(j, "noun", [](const auto& v) { return v.template get<std::string>(); });
  c.camera = field(j, "camera", [](const auto& v) { return camera_from_json(v); });
  c.visible_pixels = field(j, "visible_pixels", [](const auto& v) { return v.template get<double>(); });
  c.silhouette_pixels = field(j, "silhouette_pixels", [](const auto& v) { return v.template get<double>(); });
  const auto tip = field(j, "arrow_tip", [](const auto& v) { return v.template get<std::vector<double>>(); });
  if (tip.size() != 2) throw Error("sight label " + c.id + ": field 'arrow_tip' needs two numbers");
  c.arrow_tip = Eigen::Vector2d(tip[0], tip[1]);
  return c;
}

nlohmann::json to_json(const SightAnswer& a) {
  return {{"id", a.id}, {"rater", a.rater}, {"seen", a.seen}, {"name", a.name}, {"named", a.named}};
}

SightAnswer sight_answer_from_json(const nlohmann::json& j) {
  SightAnswer a;
  a.id = field(j, "id", [](const auto& v) { return v.template get<std::string>(); });
  a.rater = j.value("rater", std::string());
  a.seen = field(j, "seen", [](const auto& v) { return v.template get<bool>(); });
  a.name = j.value("name", std::string());
  a.named = j.value("named", a.seen);
  return a;
}

bool clearly_visible(const SightCase& c, const VisibilityOptions& rule) {
  return c.visible_pixels >= rule.min_pixels && c.share() >= rule.min_share;
}

Confusion confusion(const std::vector<SightCase>& cases, const std::vector<bool>& labels, const VisibilityOptions& rule) {
  MTG_DEMAND(cases.size() == labels.size(), "confusion: one label per case");
  Confusion out;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const bool rule_says = clearly_visible(cases[i], rule);
    if (rule_says && labels[i]) ++out.both_seen;
    if (rule_says && !labels[i]) ++out.rule_only;
    if (!rule_says && labels[i]) ++out.person_only;
    if (!rule_says && !labels[i]) ++out.neither;
  }
  return out;
}

VisibilityOptions best_thresholds(const std::vector<SightCase>& cases, const std::vector<bool>& labels,
                                  VisibilityOptions base) {
  VisibilityOptions best = base;
  int best_agree = -1;
  // Stricter first, so a tie keeps the stricter rule.
  for (int pixels = 3200; pixels >= 50; pixels -= 50) {
    for (int share = 90; share >= 5; share -= 5) {
      VisibilityOptions rule = base;
      rule.min_pixels = pixels;
      rule.min_share = share / 100.0;
      const Confusion c = confusion(cases, labels, rule);
      if (c.both_seen + c.neither > best_agree) {
        best_agree = c.both_seen + c.neither;
        best = rule;
      }
    }
  }
  return best;
}

std::vector<std::size_t> stratified_draw(const std::vector<SightCase>& cases, std::size_t count, std::uint64_t seed) {
  // Cells: visible pixels in five bands, share in four.
  auto cell = [](const SightCase& c) {
    static const double kPixels[] = {100, 400, 1600, 6400};
    static const double kShare[] = {0.3, 0.6, 0.85};
    int p = 0, s = 0;
    while (p < 4 && c.visible_pixels >= kPixels[p]) ++p;
    while (s < 3 && c.share() >= kShare[s]) ++s;
    return p * 4 + s;
  };
  std::map<int, std::vector<std::size_t>> cells;
  for (std::size_t i = 0; i < cases.size(); ++i) cells[cell(cases[i])].push_back(i);
  Rng rng(seed);
  for (auto& [k, members] : cells) rng.shuffle(members);
  std::vector<std::size_t> out;
  for (std::size_t round = 0; out.size() < count; ++round) {
    bool any = false;
    for (auto& [k, members] : cells) {
      if (round < members.size() && out.size() < count) {
        out.push_back(members[round]);
        any = true;
      }
    }
    if (!any) break;
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace mtg::render
