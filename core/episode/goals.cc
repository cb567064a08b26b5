#include "core/episode/goals.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/graph/free_space.h"
#include "core/util/error.h"

namespace mtg::episode {
namespace {

constexpr double kEps = 1e-9;

double segment_distance(const geom::Point2& p, const geom::Point2& a, const geom::Point2& b) {
  return (geom::closest_on_segment(a, b, p) - p).norm();
}

bool inside_convex(const geom::Ring& ring, const geom::Point2& p) {
  for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
    const Eigen::Vector2d e = ring[(i + 1) % n] - ring[i];
    const Eigen::Vector2d d = p - ring[i];
    if (e.x() * d.y() - e.y() * d.x() < -kEps) return false;
  }
  return ring.size() >= 3;
}

Eigen::AlignedBox2d box_in(const geom::Ring& ring_W, const Eigen::Isometry2d& X_PW) {
  return geom::bounds(geom::transform(ring_W, X_PW));
}

// Centre c (in P) lies in direction `dir` of box a, up to the limit box.
bool in_direction(const Eigen::AlignedBox2d& a, int dir, const geom::Point2& c) {
  const bool across_x = c.x() > a.min().x() && c.x() < a.max().x();
  const bool across_y = c.y() > a.min().y() && c.y() < a.max().y();
  const bool below_y = c.y() < a.min().y(), above_y = c.y() > a.max().y();
  const bool below_x = c.x() < a.min().x(), above_x = c.x() > a.max().x();
  switch (dir) {
    case 0: return across_x && below_y;
    case 1: return below_x && below_y;
    case 2: return below_x && across_y;
    case 3: return below_x && above_y;
    case 4: return across_x && above_y;
    case 5: return above_x && above_y;
    case 6: return above_x && across_y;
    default: return above_x && below_y;
  }
}

bool in_corridor(const Eigen::AlignedBox2d& a, const Eigen::AlignedBox2d& b, const geom::Point2& c) {
  // Separated along x, overlapping across y.
  const double lo_y = std::max(a.min().y(), b.min().y()), hi_y = std::min(a.max().y(), b.max().y());
  const double lo_x = std::max(a.min().x(), b.min().x()), hi_x = std::min(a.max().x(), b.max().x());
  const double gap_x0 = std::min(a.max().x(), b.max().x()), gap_x1 = std::max(a.min().x(), b.min().x());
  if (gap_x1 > gap_x0 && hi_y > lo_y && c.x() > gap_x0 && c.x() < gap_x1 && c.y() > lo_y && c.y() < hi_y) {
    return true;
  }
  const double gap_y0 = std::min(a.max().y(), b.max().y()), gap_y1 = std::max(a.min().y(), b.min().y());
  return gap_y1 > gap_y0 && hi_x > lo_x && c.y() > gap_y0 && c.y() < gap_y1 && c.x() > lo_x && c.x() < hi_x;
}

int find_or_throw(const graph::SceneGraph& g, const nlohmann::json& j, const char* key, bool platform) {
  if (!j.contains(key) || !j[key].is_string()) throw Error(std::string("goal: missing field '") + key + "'");
  const std::string name = j[key].get<std::string>();
  const int idx = platform ? g.find_platform(name) : g.find_object(name);
  if (idx < 0) throw Error(std::string("goal: ") + key + " '" + name + "' is not in scene " + g.scene);
  return idx;
}

}  // namespace

const char* to_string(GoalType type) {
  switch (type) {
    case GoalType::kSurface: return "surface";
    case GoalType::kSurfacePart: return "surface_part";
    case GoalType::kAround: return "around";
    case GoalType::kDirection: return "direction";
    case GoalType::kBetween: return "between";
  }
  return "?";
}

GoalType goal_type_from_string(const std::string& name) {
  for (const GoalType t : {GoalType::kSurface, GoalType::kSurfacePart, GoalType::kAround,
                           GoalType::kDirection, GoalType::kBetween}) {
    if (name == to_string(t)) return t;
  }
  throw Error("unknown goal type '" + name + "'");
}

const char* to_string(SetPredicate::Op op) {
  switch (op) {
    case SetPredicate::Op::kAllOn: return "all_on";
    case SetPredicate::Op::kNoneOn: return "none_on";
    case SetPredicate::Op::kNear: return "near";
    case SetPredicate::Op::kTogether: return "together";
  }
  return "?";
}

double footprint_gap(const geom::Ring& a, const geom::Ring& b) {
  for (const auto& p : a) {
    if (inside_convex(b, p)) return 0.0;
  }
  for (const auto& p : b) {
    if (inside_convex(a, p)) return 0.0;
  }
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t j = 0; j < b.size(); ++j) {
      best = std::min(best, segment_distance(a[i], b[j], b[(j + 1) % b.size()]));
      best = std::min(best, segment_distance(b[j], a[i], a[(i + 1) % a.size()]));
    }
  }
  return best;
}

bool goal_satisfied(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal,
                    const GoalOptions& options) {
  if (goal.item < 0 || s.held == goal.item) return false;
  const ObjectState& item = s.objects[static_cast<std::size_t>(goal.item)];
  if (item.parent != goal.platform) return false;
  const Eigen::Isometry2d X_PW = platform_frame(g, s, goal.platform).inverse();
  const geom::Point2 c_P = X_PW * footprint_centre(item);
  const auto side = static_cast<graph::Side>(std::max(0, item.placed_side));
  auto anchor_here = [&](int a) {
    return a >= 0 && s.objects[static_cast<std::size_t>(a)].parent == goal.platform;
  };
  switch (goal.type) {
    case GoalType::kSurface:
      return true;
    case GoalType::kSurfacePart: {
      const int dir = graph::platform_direction(goal.direction, side);
      return graph::grid_cell_rect(g.platforms[static_cast<std::size_t>(goal.platform)], dir).contains(c_P);
    }
    case GoalType::kAround:
      return anchor_here(goal.anchor) &&
             footprint_gap(item.footprint, s.objects[static_cast<std::size_t>(goal.anchor)].footprint) <=
                 options.around_distance;
    case GoalType::kDirection: {
      if (!anchor_here(goal.anchor)) return false;
      const int dir = graph::platform_direction(goal.direction, side);
      return in_direction(box_in(s.objects[static_cast<std::size_t>(goal.anchor)].footprint, X_PW), dir, c_P);
    }
    case GoalType::kBetween:
      return anchor_here(goal.anchor) && anchor_here(goal.anchor2) &&
             in_corridor(box_in(s.objects[static_cast<std::size_t>(goal.anchor)].footprint, X_PW),
                         box_in(s.objects[static_cast<std::size_t>(goal.anchor2)].footprint, X_PW), c_P);
  }
  return false;
}

bool predicate_satisfied(const graph::SceneGraph& g, const WorldState& s, const SetPredicate& p,
                         const GoalOptions& options) {
  auto on = [&](int o) { return s.held == o ? -1 : furniture_platform_of(g, s, o); };
  switch (p.op) {
    case SetPredicate::Op::kAllOn:
      return std::all_of(p.objects.begin(), p.objects.end(), [&](int o) {
        return std::find(p.platforms.begin(), p.platforms.end(), on(o)) != p.platforms.end();
      });
    case SetPredicate::Op::kNoneOn:
      return std::none_of(p.objects.begin(), p.objects.end(), [&](int o) {
        return s.held == o || std::find(p.platforms.begin(), p.platforms.end(), on(o)) != p.platforms.end();
      });
    case SetPredicate::Op::kNear: {
      if (p.objects.size() != 2) return false;
      const int a = p.objects[0], b = p.objects[1];
      return on(a) >= 0 && on(a) == on(b) &&
             footprint_gap(s.objects[static_cast<std::size_t>(a)].footprint,
                           s.objects[static_cast<std::size_t>(b)].footprint) <= options.around_distance;
    }
    case SetPredicate::Op::kTogether: {
      if (p.objects.empty()) return true;
      const int first = on(p.objects.front());
      return first >= 0 && std::all_of(p.objects.begin(), p.objects.end(), [&](int o) { return on(o) == first; });
    }
  }
  return false;
}

bool outcome_satisfied(const graph::SceneGraph& g, const WorldState& s, const OutcomeGoal& goal,
                       const GoalOptions& options) {
  if (s.held >= 0) return false;  // the paper: nothing may be held at the end
  return std::all_of(goal.all.begin(), goal.all.end(),
                     [&](const SetPredicate& p) { return predicate_satisfied(g, s, p, options); });
}

nlohmann::json to_json(const graph::SceneGraph& g, const AtomicGoal& goal) {
  auto name = [&](int o) { return g.objects[static_cast<std::size_t>(o)].name; };
  nlohmann::json j = {{"type", to_string(goal.type)},
                      {"item", name(goal.item)},
                      {"source", g.platforms[static_cast<std::size_t>(goal.source)].name},
                      {"platform", g.platforms[static_cast<std::size_t>(goal.platform)].name}};
  if (goal.anchor >= 0) j["anchor"] = name(goal.anchor);
  if (goal.anchor2 >= 0) j["anchor2"] = name(goal.anchor2);
  if (goal.direction >= 0) j["direction"] = graph::direction_name(goal.direction);
  return j;
}

AtomicGoal atomic_goal_from_json(const graph::SceneGraph& g, const nlohmann::json& j) {
  AtomicGoal goal;
  if (!j.contains("type") || !j["type"].is_string()) throw Error("goal: missing field 'type'");
  goal.type = goal_type_from_string(j["type"].get<std::string>());
  goal.item = find_or_throw(g, j, "item", false);
  goal.source = find_or_throw(g, j, "source", true);
  goal.platform = find_or_throw(g, j, "platform", true);
  if (j.contains("anchor")) goal.anchor = find_or_throw(g, j, "anchor", false);
  if (j.contains("anchor2")) goal.anchor2 = find_or_throw(g, j, "anchor2", false);
  if (j.contains("direction")) {
    const std::string d = j["direction"].get<std::string>();
    for (int k = 0; k <= graph::kCentre; ++k) {
      if (d == graph::direction_name(k)) goal.direction = k;
    }
    if (goal.direction < 0) throw Error("goal: unknown direction '" + d + "'");
  }
  return goal;
}

nlohmann::json to_json(const graph::SceneGraph& g, const OutcomeGoal& goal) {
  nlohmann::json all = nlohmann::json::array();
  for (const SetPredicate& p : goal.all) {
    std::vector<std::string> objects, platforms;
    for (const int o : p.objects) objects.push_back(g.objects[static_cast<std::size_t>(o)].name);
    for (const int q : p.platforms) platforms.push_back(g.platforms[static_cast<std::size_t>(q)].name);
    all.push_back({{"op", to_string(p.op)}, {"objects", objects}, {"platforms", platforms}});
  }
  return {{"all", all}};
}

OutcomeGoal outcome_goal_from_json(const graph::SceneGraph& g, const nlohmann::json& j) {
  OutcomeGoal goal;
  if (!j.contains("all") || !j["all"].is_array()) throw Error("outcome goal: missing array 'all'");
  for (const auto& jp : j["all"]) {
    SetPredicate p;
    const std::string op = jp.value("op", "");
    bool known = false;
    for (const auto candidate : {SetPredicate::Op::kAllOn, SetPredicate::Op::kNoneOn,
                                 SetPredicate::Op::kNear, SetPredicate::Op::kTogether}) {
      if (op == to_string(candidate)) {
        p.op = candidate;
        known = true;
      }
    }
    if (!known) throw Error("outcome goal: unknown op '" + op + "'");
    for (const auto& name : jp.value("objects", std::vector<std::string>{})) {
      const int o = g.find_object(name);
      if (o < 0) throw Error("outcome goal: object '" + name + "' is not in scene " + g.scene);
      p.objects.push_back(o);
    }
    for (const auto& name : jp.value("platforms", std::vector<std::string>{})) {
      const int q = g.find_platform(name);
      if (q < 0) throw Error("outcome goal: platform '" + name + "' is not in scene " + g.scene);
      p.platforms.push_back(q);
    }
    goal.all.push_back(std::move(p));
  }
  return goal;
}

std::vector<int> AtomicGoal::anchors() const {
  std::vector<int> out;
  if (anchor >= 0) out.push_back(anchor);
  if (anchor2 >= 0) out.push_back(anchor2);
  return out;
}

std::vector<int> TaskGoal::protected_objects() const {
  // Anchors stay put, unless a part of the task moves them itself (a Level 3 chain may use the
  // first part's item as the second part's anchor).
  std::vector<int> out;
  for (const AtomicGoal& p : parts) {
    for (const int a : p.anchors()) {
      const bool moved = std::any_of(parts.begin(), parts.end(), [&](const AtomicGoal& q) { return q.item == a; });
      if (!moved && std::find(out.begin(), out.end(), a) == out.end()) out.push_back(a);
    }
  }
  return out;
}

TaskGoal task_goal_from_json(const graph::SceneGraph& g, const nlohmann::json& goal) {
  TaskGoal out;
  if (goal.contains("atomic")) {
    out.parts.push_back(atomic_goal_from_json(g, goal["atomic"]));
  } else if (goal.contains("sequence") && goal["sequence"].is_array()) {
    for (const auto& part : goal["sequence"]) out.parts.push_back(atomic_goal_from_json(g, part));
  } else if (goal.contains("outcome")) {
    out.outcome = outcome_goal_from_json(g, goal["outcome"]);
    out.is_outcome = true;
  } else {
    throw Error("task goal: expected one of atomic, sequence, outcome");
  }
  return out;
}

bool task_goal_satisfied(const graph::SceneGraph& g, const WorldState& s, const TaskGoal& goal,
                         const GoalOptions& options) {
  if (s.held >= 0) return false;
  if (goal.is_outcome) return outcome_satisfied(g, s, goal.outcome, options);
  return !goal.parts.empty() && std::all_of(goal.parts.begin(), goal.parts.end(), [&](const AtomicGoal& p) {
    return goal_satisfied(g, s, p, options);
  });
}

}  // namespace mtg::episode
