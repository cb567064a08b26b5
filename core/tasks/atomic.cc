#include "core/tasks/atomic.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <set>

#include "core/episode/placement.h"
#include "core/graph/free_space.h"
#include "core/tasks/identify.h"
#include "core/util/error.h"
#include "core/util/parallel.h"

namespace mtg::tasks {
namespace {

using episode::AtomicGoal;
using episode::GoalType;

struct AnchorInfo {
  int object;
  Eigen::AlignedBox2d box_P;
  const geom::Ring* footprint;
};

// Identity of a goal for de-duplication (cheaper than its JSON).
std::string goal_key(const AtomicGoal& goal) {
  std::string key;
  for (const int v : {static_cast<int>(goal.type), goal.item, goal.source, goal.platform, goal.anchor, goal.anchor2,
                      goal.direction}) {
    key += std::to_string(v);
    key += '|';
  }
  return key;
}

// Candidate goals a placement with footprint centre c_P achieves on an occupied platform, found
// with box tests; each is confirmed by the judge's predicate before it becomes a task. With
// `only_anchor` >= 0, only the goals relative to that object, in the same order.
void candidate_goals(const std::vector<AnchorInfo>& anchors, const geom::Point2& c_P,
                     const geom::Ring& item_W, graph::Side side, const TaskOptions& options,
                     AtomicGoal base, int only_anchor, std::vector<AtomicGoal>& out) {
  for (std::size_t a = 0; a < anchors.size(); ++a) {
    const AnchorInfo& A = anchors[a];
    const bool wanted = only_anchor < 0 || A.object == only_anchor;
    const Eigen::AlignedBox2d& b = A.box_P;
    // around: the footprints' gap within the distance (box test first).
    const Eigen::Vector2d d = (b.min() - c_P).cwiseMax(c_P - b.max()).cwiseMax(0.0);
    if (wanted && d.norm() < options.goals.around_distance + 1.0 &&
        episode::footprint_gap(item_W, *A.footprint) <= options.goals.around_distance) {
      AtomicGoal goal = base;
      goal.type = GoalType::kAround;
      goal.anchor = A.object;
      out.push_back(goal);
    }
    // direction: which of the eight regions of the anchor holds the centre.
    const int xs = c_P.x() < b.min().x() ? -1 : (c_P.x() > b.max().x() ? 1 : 0);
    const int ys = c_P.y() < b.min().y() ? -1 : (c_P.y() > b.max().y() ? 1 : 0);
    static const std::map<std::pair<int, int>, int> kDir = {{{0, -1}, 0}, {{-1, -1}, 1}, {{-1, 0}, 2},
                                                            {{-1, 1}, 3},  {{0, 1}, 4},   {{1, 1}, 5},
                                                            {{1, 0}, 6},   {{1, -1}, 7}};
    if (const auto it = kDir.find({xs, ys}); wanted && it != kDir.end()) {
      AtomicGoal goal = base;
      goal.type = GoalType::kDirection;
      goal.anchor = A.object;
      goal.direction = graph::relative_direction(it->second, side);
      out.push_back(goal);
    }
    // between: the corridor to every other anchor.
    for (std::size_t k = a + 1; k < anchors.size(); ++k) {
      if (!wanted && anchors[k].object != only_anchor) continue;
      const Eigen::AlignedBox2d& e = anchors[k].box_P;
      const bool sep_x = std::max(b.min().x(), e.min().x()) > std::min(b.max().x(), e.max().x());
      const bool sep_y = std::max(b.min().y(), e.min().y()) > std::min(b.max().y(), e.max().y());
      if (!sep_x && !sep_y) continue;
      const double x0 = std::min(b.max().x(), e.max().x()), x1 = std::max(b.min().x(), e.min().x());
      const double y0 = std::min(b.max().y(), e.max().y()), y1 = std::max(b.min().y(), e.min().y());
      const double ox0 = std::max(b.min().x(), e.min().x()), ox1 = std::min(b.max().x(), e.max().x());
      const double oy0 = std::max(b.min().y(), e.min().y()), oy1 = std::min(b.max().y(), e.max().y());
      const bool in_x = sep_x && c_P.x() > x0 && c_P.x() < x1 && c_P.y() > oy0 && c_P.y() < oy1;
      const bool in_y = sep_y && c_P.y() > y0 && c_P.y() < y1 && c_P.x() > ox0 && c_P.x() < ox1;
      if (in_x || in_y) {
        AtomicGoal goal = base;
        goal.type = GoalType::kBetween;
        goal.anchor = std::min(A.object, anchors[k].object);
        goal.anchor2 = std::max(A.object, anchors[k].object);
        out.push_back(goal);
      }
    }
  }
}

// The held item put down at one placement target for as long as this lives, then everything
// as it was: the parts of the world a placement changes are saved and restored (not moved
// back, which would not give the same bits), instead of copying the whole world per target.
class TrialPlacement {
 public:
  TrialPlacement(const graph::SceneGraph& g, episode::WorldState& s, int platform, const Eigen::Vector2d& xy)
      : s_(s), platform_(platform), held_(s.held) {
    std::vector<int> moving = {held_};
    for (const int p : g.objects[static_cast<std::size_t>(held_)].platforms) {
      for (const int o : episode::everything_on(g, s, p)) moving.push_back(o);
    }
    for (const int o : moving) {
      objects_.emplace_back(o, s.objects[static_cast<std::size_t>(o)]);
      for (const int p : g.objects[static_cast<std::size_t>(o)].platforms) {
        offsets_.emplace_back(p, s.platform_offset[static_cast<std::size_t>(p)]);
      }
    }
    episode::place_held(g, s, platform, xy);
  }
  ~TrialPlacement() {
    for (const auto& [o, state] : objects_) s_.objects[static_cast<std::size_t>(o)] = state;
    for (const auto& [p, offset] : offsets_) s_.platform_offset[static_cast<std::size_t>(p)] = offset;
    s_.children[static_cast<std::size_t>(platform_)].pop_back();  // place_held appended the item
    s_.held = held_;
  }
  TrialPlacement(const TrialPlacement&) = delete;
  TrialPlacement& operator=(const TrialPlacement&) = delete;

 private:
  episode::WorldState& s_;
  int platform_;
  int held_;
  std::vector<std::pair<int, episode::ObjectState>> objects_;
  std::vector<std::pair<int, Eigen::Vector3d>> offsets_;
};

}  // namespace

std::vector<AtomicTask> enumerate_atomic(const graph::SceneGraph& g, const episode::WorldState& s,
                                         const TaskOptions& options, const AtomicFilter& filter, DropCounts* dropped,
                                         int jobs) {
  MTG_DEMAND(dropped == nullptr || (filter.goal_key.empty() && filter.anchor < 0),
             "drop counts of a partial enumeration would be partial");
  auto wanted = [](const std::vector<int>& list, int v) {
    return list.empty() || std::find(list.begin(), list.end(), v) != list.end();
  };
  auto build_targets = [&](const episode::WorldState& placing, int pd, graph::Side side) {
    std::vector<episode::PlaceTarget> t = episode::place_targets(g, placing, pd, side, options.rules.min_region_size);
    std::stable_partition(t.begin(), t.end(),
                          [](const episode::PlaceTarget& x) { return x.key == episode::kAnywhereKey; });
    episode::with_insets(t);
    return t;
  };
  // Placement targets of each destination as the initial state offers them; shared (not copied)
  // by every item that does not come from that destination (its obstacles are then the same).
  // Items run in parallel (each has its own goals and drops), so the cache is shared under a lock;
  // map nodes stay where they are, so a reference handed out stays valid.
  std::map<int, std::vector<episode::PlaceTarget>> cached_targets;
  std::mutex cache_mutex;
  auto cached_targets_for = [&](const episode::WorldState& placing, int pd,
                                graph::Side side) -> const std::vector<episode::PlaceTarget>& {
    const std::lock_guard<std::mutex> lock(cache_mutex);
    auto it = cached_targets.find(pd);
    if (it == cached_targets.end()) it = cached_targets.emplace(pd, build_targets(placing, pd, side)).first;
    return it->second;
  };
  // Every item to enumerate, in output order: source platforms by label, items in o-order.
  struct Source {
    std::size_t src_label, k;
    int item;
  };
  std::vector<Source> sources;
  for (std::size_t src_label = 0; src_label < g.navigable.size(); ++src_label) {
    const std::vector<int> items = episode::pickable_on(g, s, g.navigable[src_label]);
    for (std::size_t k = 0; k < items.size(); ++k) {
      if (wanted(filter.items, items[k])) sources.push_back({src_label, k, items[k]});
    }
  }
  struct Found {
    std::vector<AtomicTask> tasks;
    DropCounts dropped;
  };
  std::vector<Found> found(sources.size());
  parallel_for(sources.size(), jobs, [&](std::size_t i) {
    const auto [src_label, k, item] = sources[i];
    const int ps = g.navigable[src_label];
    std::vector<AtomicTask>& out = found[i].tasks;
    episode::WorldState held = s;
    held.at_platform = ps;
    held.side = g.platforms[static_cast<std::size_t>(ps)].default_side;
    held.phase = episode::Phase::kAtPlatform;
    episode::pick(g, held, item);
    const double own_height = held.objects[static_cast<std::size_t>(item)].top -
                              held.objects[static_cast<std::size_t>(item)].bottom;
    const double carried_height = episode::stack_height(g, held, item);
    std::set<std::string> seen;
    std::map<std::string, std::pair<AtomicGoal, const char*>> rejected;  // goal key -> why
    for (std::size_t dst_label = 0; dst_label < g.navigable.size(); ++dst_label) {
      const int pd = g.navigable[dst_label];
      if (!wanted(filter.destinations, pd)) continue;
      const graph::Platform& dest = g.platforms[static_cast<std::size_t>(pd)];
      if (own_height > dest.clearance) continue;
      // Taller with what rests on it: the goals are counted, never offered.
      const bool too_tall = carried_height > dest.clearance;
      episode::WorldState placing = held;
      placing.at_platform = pd;
      placing.side = dest.default_side;
      placing.phase = episode::Phase::kPlacing;
      const auto side = static_cast<graph::Side>(dest.default_side);
      const episode::FeasibleCentres feasible = episode::held_feasible_centres(g, placing, pd);
      if (feasible.empty()) continue;
      const bool from_here = episode::objects_on(placing, pd) != episode::objects_on(s, pd);
      std::vector<episode::PlaceTarget> own_targets;
      if (from_here) own_targets = build_targets(placing, pd, side);
      const std::vector<episode::PlaceTarget>& targets =
          from_here ? own_targets : cached_targets_for(placing, pd, side);
      const geom::Ring item_rel_P = episode::held_footprint_P(g, placing, pd);
      // At least min_goal_area of centre positions meet the goal and fit. A disk of that area
      // around the placement, inside both, settles it without clipping polygons.
      const auto roomy = [&](const AtomicGoal& goal, double margin, const geom::Point2& c_P) {
        const double r = std::sqrt(options.min_goal_area / std::numbers::pi);
        if (margin >= r && geom::contains(feasible.all, c_P) && geom::distance_to_boundary(feasible.all, c_P) >= r) {
          return true;
        }
        const geom::Region goal_P = episode::goal_region_P(g, placing, goal, side, item_rel_P, options.goals);
        return geom::area(geom::intersect(goal_P, feasible.all)) >= options.min_goal_area;
      };
      // Anchors: everything on the destination now, in the frame of the platform.
      const Eigen::Isometry2d X_PW = episode::platform_frame(g, placing, pd).inverse();
      std::vector<AnchorInfo> anchors;
      for (const int o : episode::objects_on(placing, pd)) {
        const geom::Ring& fp = placing.objects[static_cast<std::size_t>(o)].footprint;
        anchors.push_back({o, geom::bounds(geom::transform(fp, X_PW)), &fp});
      }
      if (filter.anchor >= 0 && std::none_of(anchors.begin(), anchors.end(),
                                             [&](const AnchorInfo& a) { return a.object == filter.anchor; })) {
        continue;
      }
      AtomicGoal base;
      base.item = item;
      base.source = ps;
      base.platform = pd;
      // The goals a placement at xy may achieve, with their keys and margins, judged with the
      // item put down there; the item is back in hand when this returns.
      struct Candidate {
        AtomicGoal goal;
        std::string key;
        double margin = 0.0;  // 0 for a key already taken (skipped after, so not judged)
      };
      struct Judged {
        std::vector<Candidate> candidates;
        geom::Point2 c_P;
        Eigen::Vector3d placed_at;
      };
      auto judge_at = [&](const Eigen::Vector2d& xy) {
        Judged j;
        const TrialPlacement trial(g, placing, pd, xy);
        const auto& moved = placing.objects[static_cast<std::size_t>(item)];
        j.c_P = X_PW * episode::footprint_centre(moved);
        j.placed_at = moved.position;
        std::vector<AtomicGoal> goals;
        if (pd != ps) {
          AtomicGoal surface = base;
          goals.push_back(surface);
        }
        if (anchors.empty()) {
          for (int rel = 0; rel <= graph::kCentre; ++rel) {
            AtomicGoal part = base;
            part.type = GoalType::kSurfacePart;
            part.direction = rel;
            goals.push_back(part);
          }
        } else {
          candidate_goals(anchors, j.c_P, moved.footprint, side, options, base, filter.anchor, goals);
        }
        for (const AtomicGoal& goal : goals) {
          if (filter.anchor >= 0) {  // the surface and its parts have no anchor
            const auto a = goal.anchors();
            if (std::find(a.begin(), a.end(), filter.anchor) == a.end()) continue;
          }
          std::string key = goal_key(goal);
          if (!filter.goal_key.empty() && key != filter.goal_key) continue;
          const double margin = seen.count(key) != 0 ? 0.0 : episode::goal_margin(g, placing, goal, options.goals);
          j.candidates.push_back({goal, std::move(key), margin});
        }
        return j;
      };
      for (const episode::PlaceTarget& t : targets) {
        const auto xy = episode::resolve_target(g, placing, pd, t, feasible);
        if (!xy) continue;
        Judged judged = judge_at(*xy);
        const geom::Point2& c_P = judged.c_P;
        for (Candidate& candidate : judged.candidates) {
          const AtomicGoal& goal = candidate.goal;
          std::string& key = candidate.key;
          if (seen.count(key) != 0) continue;
          const double margin = candidate.margin;
          if (margin <= 0.0) continue;  // not a goal of this placement: the judge decides
          const char* why = nullptr;
          if (too_tall) {
            why = "stack";
          } else if (episode::goal_met_from_any_side(g, s, goal, options.goals)) {
            why = "trivial";
          } else if (margin < options.min_margin) {
            why = "fragile";
          } else if (!roomy(goal, margin, c_P)) {
            why = "small_area";
          }
          if (why != nullptr) {
            rejected.emplace(key, std::make_pair(goal, why));  // another key may still achieve it
            continue;
          }
          seen.insert(key);
          AtomicTask task;
          task.goal = goal;
          task.key = std::move(key);
          task.oracle = {graph::navigation_key(static_cast<int>(src_label) + 1), "o" + std::to_string(k + 1),
                         graph::navigation_key(static_cast<int>(dst_label) + 1), "startplace", t.key};
          task.place_xy = *xy;
          task.placed_at = judged.placed_at;
          task.margin = margin;
          out.push_back(std::move(task));
          if (!filter.goal_key.empty()) return;  // the one goal asked for, where it is first achieved
        }
      }
    }
    if (dropped == nullptr) return;
    for (const auto& [key, why] : rejected) {
      if (seen.count(key) == 0) {
        found[i].dropped.add(why.second, has_lookalikes(g, s, why.first, options.ambiguity) ? 2 : 1);
      }
    }
  });
  std::vector<AtomicTask> out;
  for (Found& f : found) {
    for (AtomicTask& t : f.tasks) out.push_back(std::move(t));
    if (dropped != nullptr) dropped->merge(f.dropped);
    if (!filter.goal_key.empty() && !out.empty()) break;  // a key names one item: at most one has it
  }
  return out;
}

void apply_effect(const graph::SceneGraph& g, episode::WorldState& s, const AtomicTask& task) {
  const graph::Platform& dest = g.platforms[static_cast<std::size_t>(task.goal.platform)];
  episode::pick(g, s, task.goal.item);
  s.at_platform = task.goal.platform;
  s.side = dest.default_side;
  episode::place_held(g, s, task.goal.platform, task.place_xy);
  s.phase = episode::Phase::kAtPlatform;
  s.steps += static_cast<int>(task.oracle.size());
}

}  // namespace mtg::tasks
