#include "core/episode/goals.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "core/graph/free_space.h"
#include "core/util/error.h"

namespace mtg::episode {
namespace {

constexpr double kEps = 1e-9;
constexpr double kPruneMargin = 1e-9;  // m: far above the rounding of a distance at metre-scale coordinates
constexpr double kInf = std::numeric_limits<double>::infinity();

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

// The footprint-centre positions (in P) of a direction of box a: beyond its edge and within its
// extent across (sides), or beyond both edges (corners). Unbounded away from the anchor.
Eigen::AlignedBox2d direction_box(const Eigen::AlignedBox2d& a, int dir) {
  // Along x and along y, the interval the step points to: -1 below the box, 0 across it, +1 above it.
  auto interval = [](double lo, double hi, int span) {
    return span < 0 ? Eigen::Vector2d(-kInf, lo) : span > 0 ? Eigen::Vector2d(hi, kInf) : Eigen::Vector2d(lo, hi);
  };
  const Eigen::Vector2i step = graph::direction_step(dir);
  const Eigen::Vector2d x = interval(a.min().x(), a.max().x(), step.x());
  const Eigen::Vector2d y = interval(a.min().y(), a.max().y(), step.y());
  return {Eigen::Vector2d(x[0], y[0]), Eigen::Vector2d(x[1], y[1])};
}

// The corridor between two boxes: between their facing edges and within the overlap of their
// extents across. Empty when they overlap or their extents across do not.
Eigen::AlignedBox2d corridor_box(const Eigen::AlignedBox2d& a, const Eigen::AlignedBox2d& b) {
  const double lo_y = std::max(a.min().y(), b.min().y()), hi_y = std::min(a.max().y(), b.max().y());
  const double lo_x = std::max(a.min().x(), b.min().x()), hi_x = std::min(a.max().x(), b.max().x());
  const double gap_x0 = std::min(a.max().x(), b.max().x()), gap_x1 = std::max(a.min().x(), b.min().x());
  if (gap_x1 > gap_x0 && hi_y > lo_y) return {Eigen::Vector2d(gap_x0, lo_y), Eigen::Vector2d(gap_x1, hi_y)};
  const double gap_y0 = std::min(a.max().y(), b.max().y()), gap_y1 = std::max(a.min().y(), b.min().y());
  if (gap_y1 > gap_y0 && hi_x > lo_x) return {Eigen::Vector2d(lo_x, gap_y0), Eigen::Vector2d(hi_x, gap_y1)};
  return {};
}

// How far c lies inside the open box (<= 0 when outside or the box is empty).
double inside_by(const Eigen::AlignedBox2d& box, const geom::Point2& c) {
  if (box.isEmpty()) return 0.0;
  return std::min({c.x() - box.min().x(), box.max().x() - c.x(), c.y() - box.min().y(), box.max().y() - c.y()});
}

bool side_dependent(GoalType type) { return type == GoalType::kSurfacePart || type == GoalType::kDirection; }

bool on_destination(const WorldState& s, const AtomicGoal& goal) {
  return goal.item.valid() && s.held != goal.item && s.objects[goal.item].parent == goal.platform;
}

// What a goal asks of the item's footprint centre, as a box in the destination frame P, for the
// box goals (part, direction, between). `applies` is false when a named anchor is not there.
struct CentreBox {
  bool applies = false;
  Eigen::AlignedBox2d box_P;
};

CentreBox centre_box(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal, graph::Side side) {
  auto anchor_here = [&](graph::ObjectId a) { return a.valid() && s.objects[a].parent == goal.platform; };
  const Eigen::Isometry2d X_PW = platform_frame(g, s, goal.platform).inverse();
  auto anchor_box = [&](graph::ObjectId a) { return box_in(s.objects[a].footprint, X_PW); };
  switch (goal.type) {
    case GoalType::kSurfacePart:
      return {true, graph::grid_cell_rect(g.platforms[goal.platform],
                                          graph::platform_direction(goal.direction, side))};
    case GoalType::kDirection:
      if (!anchor_here(goal.anchor)) return {};
      return {true, direction_box(anchor_box(goal.anchor), graph::platform_direction(goal.direction, side))};
    case GoalType::kBetween:
      if (!anchor_here(goal.anchor) || !anchor_here(goal.anchor2)) return {};
      return {true, corridor_box(anchor_box(goal.anchor), anchor_box(goal.anchor2))};
    case GoalType::kSurface:
    case GoalType::kAround:
      break;
  }
  MTG_DEMAND(false, std::string("centre_box of a ") + to_string(goal.type) + " goal");
  return {};
}

// The goal's margin for the item standing on the destination, named from `side`.
double margin_from(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal, graph::Side side,
                   const GoalOptions& options) {
  const ObjectState& item = s.objects[goal.item];
  switch (goal.type) {
    case GoalType::kSurface:
      return kInf;
    case GoalType::kAround: {
      const ObjectState& anchor = s.objects[goal.anchor];
      if (anchor.parent != goal.platform) return 0.0;
      return options.around_distance - footprint_gap(item.footprint, anchor.footprint);
    }
    default: {
      const CentreBox box = centre_box(g, s, goal, side);
      if (!box.applies) return 0.0;
      return inside_by(box.box_P, platform_frame(g, s, goal.platform).inverse() * footprint_centre(item));
    }
  }
}

// The object (Id = graph::ObjectId) or platform (graph::PlatformId) j[key] names.
template <class Id>
Id find_or_throw(const graph::SceneGraph& g, const nlohmann::json& j, const char* key) {
  if (!j.contains(key) || !j[key].is_string()) throw Error(std::string("goal: missing field '") + key + "'");
  const std::string name = j[key].get<std::string>();
  Id id;
  if constexpr (std::is_same_v<Id, graph::PlatformId>) {
    id = g.find_platform(name);
  } else {
    id = g.find_object(name);
  }
  if (!id.valid()) throw Error(std::string("goal: ") + key + " '" + name + "' is not in scene " + g.scene);
  return id;
}

std::vector<graph::ObjectId> objects_from_json(const graph::SceneGraph& g, const nlohmann::json& jp, const char* key) {
  std::vector<graph::ObjectId> out;
  for (const auto& name : jp.value(key, std::vector<std::string>{})) {
    const graph::ObjectId o = g.find_object(name);
    if (!o.valid()) throw Error("outcome goal: object '" + name + "' is not in scene " + g.scene);
    out.push_back(o);
  }
  return out;
}

constexpr SetPredicate::Op kAllOps[] = {SetPredicate::Op::kAllOn,    SetPredicate::Op::kNoneOn,
                                        SetPredicate::Op::kNear,     SetPredicate::Op::kTogether,
                                        SetPredicate::Op::kAnyPairNear, SetPredicate::Op::kCountOn,
                                        SetPredicate::Op::kApart,    SetPredicate::Op::kAllNear,
                                        SetPredicate::Op::kNoneNear};

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
    case SetPredicate::Op::kAnyPairNear: return "any_pair_near";
    case SetPredicate::Op::kCountOn: return "count_on";
    case SetPredicate::Op::kApart: return "apart";
    case SetPredicate::Op::kAllNear: return "all_near";
    case SetPredicate::Op::kNoneNear: return "none_near";
  }
  return "?";
}

bool uses_objects2(SetPredicate::Op op) {
  return op == SetPredicate::Op::kAnyPairNear || op == SetPredicate::Op::kAllNear || op == SetPredicate::Op::kNoneNear;
}

double footprint_gap(const geom::Ring& a, const geom::Ring& b) {
  for (const auto& p : a) {
    if (inside_convex(b, p)) return 0.0;
  }
  for (const auto& p : b) {
    if (inside_convex(a, p)) return 0.0;
  }
  // The smallest distance from a vertex of either ring to an edge of the other. A vertex farther
  // from the other ring's box than the best so far cannot lower it (the margin dwarfs rounding),
  // so its edges are skipped: the minimum, and so every verdict, is the same to the bit.
  double best = std::numeric_limits<double>::infinity();
  const auto vertex_to_edges = [&best](const geom::Point2& p, const geom::Ring& ring, const Eigen::AlignedBox2d& box) {
    const double below = (box.min() - p).cwiseMax(p - box.max()).cwiseMax(0.0).norm();
    if (below > best + kPruneMargin) return;
    for (std::size_t j = 0, n = ring.size(); j < n; ++j) {
      best = std::min(best, segment_distance(p, ring[j], ring[(j + 1) % n]));
    }
  };
  const Eigen::AlignedBox2d box_a = geom::bounds(a), box_b = geom::bounds(b);
  for (const auto& p : a) vertex_to_edges(p, b, box_b);
  for (const auto& p : b) vertex_to_edges(p, a, box_a);
  return best;
}

double footprint_gap_up_to(const geom::Ring& a, const Eigen::AlignedBox2d& box_a, const geom::Ring& b,
                           const Eigen::AlignedBox2d& box_b, double limit) {
  // Each footprint lies in its box, so the boxes are no farther apart than the footprints; the
  // margin keeps a gap that rounds either side of `limit` on the exact path.
  const double boxes = (box_a.min() - box_b.max()).cwiseMax(box_b.min() - box_a.max()).cwiseMax(0.0).norm();
  if (boxes > limit + kPruneMargin) return boxes;
  return footprint_gap(a, b);
}

bool goal_satisfied(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal,
                    const GoalOptions& options) {
  return goal_margin(g, s, goal, options) > 0.0;
}

double goal_margin(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal,
                   const GoalOptions& options) {
  if (!on_destination(s, goal)) return 0.0;
  const int placed_side = s.objects[goal.item].placed_side;
  if (side_dependent(goal.type) && placed_side < 0) return 0.0;  // never placed: no side to name from
  return std::max(0.0, margin_from(g, s, goal, static_cast<graph::Side>(std::max(0, placed_side)), options));
}

bool goal_met_from_any_side(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal,
                            const GoalOptions& options) {
  if (!on_destination(s, goal)) return false;
  if (!side_dependent(goal.type)) return margin_from(g, s, goal, graph::Side::kRear, options) > 0.0;
  const graph::Platform& p = g.platforms[goal.platform];
  for (const graph::Side side : graph::kSides) {
    // Only where the robot can stand: no one names directions from elsewhere.
    const bool usable = p.sides[static_cast<std::size_t>(side)].usable() || static_cast<int>(side) == p.default_side;
    if (usable && margin_from(g, s, goal, side, options) > 0.0) return true;
  }
  return false;
}

geom::Region goal_region_P(const graph::SceneGraph& g, const WorldState& s, const AtomicGoal& goal,
                           graph::Side side, const geom::Ring& item_rel_P, const GoalOptions& options) {
  const graph::Platform& p = g.platforms[goal.platform];
  const geom::Region bounds = geom::rectangle(p.box_P.min(), p.box_P.max());
  switch (goal.type) {
    case GoalType::kSurface:
      return bounds;
    case GoalType::kAround: {
      const ObjectState& anchor = s.objects[goal.anchor];
      if (anchor.parent != goal.platform) return {};
      const Eigen::Isometry2d X_PW = platform_frame(g, s, goal.platform).inverse();
      const geom::Region anchor_P = geom::from_ring(geom::transform(anchor.footprint, X_PW));
      return geom::intersect(
          geom::dilate(geom::offset(anchor_P, options.around_distance), geom::mirrored(item_rel_P)), bounds);
    }
    default: {
      const CentreBox box = centre_box(g, s, goal, side);
      if (!box.applies) return {};
      const Eigen::AlignedBox2d clipped = box.box_P.intersection(p.box_P);
      if (clipped.isEmpty() || (clipped.sizes().array() <= 0.0).any()) return {};
      return geom::rectangle(clipped.min(), clipped.max());
    }
  }
}

bool predicate_satisfied(const graph::SceneGraph& g, const WorldState& s, const SetPredicate& p,
                         const GoalOptions& options) {
  auto on = [&](graph::ObjectId o) { return s.held == o ? graph::PlatformId() : furniture_platform_of(g, s, o); };
  auto near = [&](graph::ObjectId a, graph::ObjectId b) {
    return a != b && on(a).valid() && on(a) == on(b) &&
           footprint_gap(s.objects[a].footprint,
                         s.objects[b].footprint) <= options.around_distance;
  };
  auto listed = [](const std::vector<graph::PlatformId>& list, graph::PlatformId v) {
    return std::find(list.begin(), list.end(), v) != list.end();
  };
  switch (p.op) {
    case SetPredicate::Op::kAllOn:
      return std::all_of(p.objects.begin(), p.objects.end(),
                         [&](graph::ObjectId o) { return listed(p.platforms, on(o)); });
    case SetPredicate::Op::kNoneOn:
      return std::none_of(p.objects.begin(), p.objects.end(),
                          [&](graph::ObjectId o) { return s.held == o || listed(p.platforms, on(o)); });
    case SetPredicate::Op::kNear:
      return p.objects.size() == 2 && near(p.objects[0], p.objects[1]);
    case SetPredicate::Op::kTogether: {
      if (p.objects.empty()) return true;
      const graph::PlatformId first = on(p.objects.front());
      return first.valid() &&
             std::all_of(p.objects.begin(), p.objects.end(), [&](graph::ObjectId o) { return on(o) == first; });
    }
    case SetPredicate::Op::kAnyPairNear:
      return std::any_of(p.objects.begin(), p.objects.end(), [&](graph::ObjectId a) {
        return listed(p.platforms, on(a)) &&
               std::any_of(p.objects2.begin(), p.objects2.end(), [&](graph::ObjectId b) { return near(a, b); });
      });
    case SetPredicate::Op::kCountOn: {
      const auto n = std::count_if(p.objects.begin(), p.objects.end(),
                                   [&](graph::ObjectId o) { return listed(p.platforms, on(o)); });
      return n >= p.min && n <= p.max;
    }
    case SetPredicate::Op::kApart: {
      std::vector<graph::PlatformId> used;
      for (const graph::ObjectId o : p.objects) {
        const graph::PlatformId at = on(o);
        if (!at.valid() || listed(used, at)) return false;
        used.push_back(at);
      }
      return true;
    }
    case SetPredicate::Op::kAllNear:
      return std::all_of(p.objects.begin(), p.objects.end(), [&](graph::ObjectId a) {
        return std::any_of(p.objects2.begin(), p.objects2.end(), [&](graph::ObjectId b) { return near(a, b); });
      });
    case SetPredicate::Op::kNoneNear:
      return std::none_of(p.objects.begin(), p.objects.end(), [&](graph::ObjectId a) {
        return std::any_of(p.objects2.begin(), p.objects2.end(), [&](graph::ObjectId b) { return near(a, b); });
      });
  }
  return false;
}

bool outcome_satisfied(const graph::SceneGraph& g, const WorldState& s, const OutcomeGoal& goal,
                       const GoalOptions& options) {
  if (s.held.valid()) return false;  // the paper: nothing may be held at the end
  return std::all_of(goal.all.begin(), goal.all.end(),
                     [&](const SetPredicate& p) { return predicate_satisfied(g, s, p, options); });
}

nlohmann::json to_json(const graph::SceneGraph& g, const AtomicGoal& goal) {
  auto name = [&](graph::ObjectId o) { return g.objects[o].name; };
  nlohmann::json j = {{"type", to_string(goal.type)},
                      {"item", name(goal.item)},
                      {"source", g.platforms[goal.source].name},
                      {"platform", g.platforms[goal.platform].name}};
  if (goal.anchor.valid()) j["anchor"] = name(goal.anchor);
  if (goal.anchor2.valid()) j["anchor2"] = name(goal.anchor2);
  if (goal.direction >= 0) j["direction"] = graph::direction_name(goal.direction);
  return j;
}

AtomicGoal atomic_goal_from_json(const graph::SceneGraph& g, const nlohmann::json& j) {
  AtomicGoal goal;
  if (!j.contains("type") || !j["type"].is_string()) throw Error("goal: missing field 'type'");
  goal.type = goal_type_from_string(j["type"].get<std::string>());
  goal.item = find_or_throw<graph::ObjectId>(g, j, "item");
  goal.source = find_or_throw<graph::PlatformId>(g, j, "source");
  goal.platform = find_or_throw<graph::PlatformId>(g, j, "platform");
  if (j.contains("anchor")) goal.anchor = find_or_throw<graph::ObjectId>(g, j, "anchor");
  if (j.contains("anchor2")) goal.anchor2 = find_or_throw<graph::ObjectId>(g, j, "anchor2");
  if (j.contains("direction")) {
    const std::string d = j["direction"].get<std::string>();
    for (int k = 0; k <= graph::kCentre; ++k) {
      if (d == graph::direction_name(k)) goal.direction = k;
    }
    if (goal.direction < 0) throw Error("goal: unknown direction '" + d + "'");
  }
  const bool needs_anchor = goal.type == GoalType::kAround || goal.type == GoalType::kDirection ||
                            goal.type == GoalType::kBetween;
  if (needs_anchor && !goal.anchor.valid()) {
    throw Error(std::string("goal: a ") + to_string(goal.type) + " goal needs 'anchor'");
  }
  if (goal.type == GoalType::kBetween && !goal.anchor2.valid()) throw Error("goal: a between goal needs 'anchor2'");
  if (side_dependent(goal.type) && goal.direction < 0) {
    throw Error(std::string("goal: a ") + to_string(goal.type) + " goal needs 'direction'");
  }
  return goal;
}

nlohmann::json to_json(const graph::SceneGraph& g, const OutcomeGoal& goal) {
  auto names = [&](const std::vector<graph::ObjectId>& objects) {
    std::vector<std::string> out;
    for (const graph::ObjectId o : objects) out.push_back(g.objects[o].name);
    return out;
  };
  nlohmann::json all = nlohmann::json::array();
  for (const SetPredicate& p : goal.all) {
    std::vector<std::string> platforms;
    for (const graph::PlatformId q : p.platforms) platforms.push_back(g.platforms[q].name);
    nlohmann::json jp = {{"op", to_string(p.op)}, {"objects", names(p.objects)}, {"platforms", platforms}};
    if (!p.objects2.empty()) jp["objects2"] = names(p.objects2);
    if (p.op == SetPredicate::Op::kCountOn) {
      jp["min"] = p.min;
      jp["max"] = p.max;
    }
    all.push_back(std::move(jp));
  }
  return {{"all", all}};
}

OutcomeGoal outcome_goal_from_json(const graph::SceneGraph& g, const nlohmann::json& j) {
  OutcomeGoal goal;
  if (!j.contains("all") || !j["all"].is_array()) throw Error("outcome goal: missing array 'all'");
  for (const auto& jp : j["all"]) {
    SetPredicate p;
    const std::string op = jp.value("op", "");
    const auto* known = std::find_if(std::begin(kAllOps), std::end(kAllOps),
                                     [&](SetPredicate::Op candidate) { return op == to_string(candidate); });
    if (known == std::end(kAllOps)) throw Error("outcome goal: unknown op '" + op + "'");
    p.op = *known;
    p.objects = objects_from_json(g, jp, "objects");
    p.objects2 = objects_from_json(g, jp, "objects2");
    if (p.op == SetPredicate::Op::kCountOn) {
      for (auto [field, value] : {std::pair{"min", &p.min}, std::pair{"max", &p.max}}) {
        if (!jp.contains(field) || !jp[field].is_number_integer() || jp[field].get<long long>() < 0 ||
            jp[field].get<long long>() > 1000) {
          throw Error(std::string("outcome goal: a count_on predicate needs an integer '") + field + "' from 0 to 1000");
        }
        *value = jp[field].get<int>();
      }
      if (p.min > p.max) throw Error("outcome goal: count_on's 'min' is above its 'max'");
    }
    if (uses_objects2(p.op) && p.objects2.empty()) {
      throw Error(std::string("outcome goal: a ") + op + " predicate needs 'objects2'");
    }
    for (const auto& name : jp.value("platforms", std::vector<std::string>{})) {
      const graph::PlatformId q = g.find_platform(name);
      if (!q.valid()) throw Error("outcome goal: platform '" + name + "' is not in scene " + g.scene);
      p.platforms.push_back(q);
    }
    goal.all.push_back(std::move(p));
  }
  return goal;
}

std::vector<graph::ObjectId> AtomicGoal::anchors() const {
  std::vector<graph::ObjectId> out;
  if (anchor.valid()) out.push_back(anchor);
  if (anchor2.valid()) out.push_back(anchor2);
  return out;
}

std::vector<graph::ObjectId> TaskGoal::protected_objects() const {
  // Anchors stay put, unless a part of the task moves them itself (a Level 3 chain may use the
  // first part's item as the second part's anchor).
  std::vector<graph::ObjectId> out;
  for (const AtomicGoal& p : parts) {
    for (const graph::ObjectId a : p.anchors()) {
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
  if (s.held.valid()) return false;
  if (goal.is_outcome) return outcome_satisfied(g, s, goal.outcome, options);
  return !goal.parts.empty() && std::all_of(goal.parts.begin(), goal.parts.end(), [&](const AtomicGoal& p) {
    return goal_satisfied(g, s, p, options);
  });
}

}  // namespace mtg::episode
