#include "core/tasks/atomic.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>
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
  graph::ObjectId object;
  Eigen::AlignedBox2d box_P;
  const geom::Ring* footprint;
  Eigen::AlignedBox2d box_W;  // the footprint's
};

// Identity of a goal for de-duplication (cheaper than its JSON).
std::string goal_key(const AtomicGoal& goal) {
  std::string key;
  for (const int v : {static_cast<int>(goal.type), goal.item.value(), goal.source.value(), goal.platform.value(),
                      goal.anchor.value(), goal.anchor2.value(), goal.direction}) {
    key += std::to_string(v);
    key += '|';
  }
  return key;
}

constexpr double kBetweenMaxGap = 0.4;  // m between two anchors of a "between" goal, at most

// How two anchors' boxes lie apart (platform frame): separated along x, along y, and whether
// a "between" goal joins them. Far apart (two ends of a counter), "between" is a long band a
// person cannot see: only anchors within kBetweenMaxGap of each other make one.
struct Apart {
  bool x = false;
  bool y = false;
  bool between = false;
};
Apart apart_of(const Eigen::AlignedBox2d& b, const Eigen::AlignedBox2d& e) {
  Apart out;
  out.x = std::max(b.min().x(), e.min().x()) > std::min(b.max().x(), e.max().x());
  out.y = std::max(b.min().y(), e.min().y()) > std::min(b.max().y(), e.max().y());
  const double gap = std::max(out.x ? std::max(b.min().x(), e.min().x()) - std::min(b.max().x(), e.max().x()) : 0.0,
                              out.y ? std::max(b.min().y(), e.min().y()) - std::min(b.max().y(), e.max().y()) : 0.0);
  out.between = (out.x || out.y) && gap <= kBetweenMaxGap;
  return out;
}

// Candidate goals a placement with footprint centre c_P achieves on an occupied platform, found
// with box tests; each is confirmed by the judge's predicate before it becomes a task. With
// a valid `only_anchor`, only the goals relative to that object, in the same order.
void candidate_goals(const std::vector<AnchorInfo>& anchors, const geom::Point2& c_P,
                     const geom::Ring& item_W, const Eigen::AlignedBox2d& item_box_W, graph::Side side, const TaskOptions& options,
                     AtomicGoal base, graph::ObjectId only_anchor, std::vector<AtomicGoal>& out) {
  for (std::size_t a = 0; a < anchors.size(); ++a) {
    const AnchorInfo& A = anchors[a];
    const bool wanted = !only_anchor.valid() || A.object == only_anchor;
    const Eigen::AlignedBox2d& b = A.box_P;
    // around: the footprints' gap within the distance. The test of the item's centre against the
    // anchor's box (1 m of slack) leaves out items reaching farther than that from their centre;
    // it is what the task sets were made with, so it stays.
    const double around = options.goals.around_distance;
    const Eigen::Vector2d d = (b.min() - c_P).cwiseMax(c_P - b.max()).cwiseMax(0.0);
    if (wanted && d.norm() < around + 1.0 &&
        episode::footprint_gap_up_to(item_W, item_box_W, *A.footprint, A.box_W, around) <= around) {
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
      const Apart apart = apart_of(b, e);
      if (!apart.between) continue;
      const double x0 = std::min(b.max().x(), e.max().x()), x1 = std::max(b.min().x(), e.min().x());
      const double y0 = std::min(b.max().y(), e.max().y()), y1 = std::max(b.min().y(), e.min().y());
      const double ox0 = std::max(b.min().x(), e.min().x()), ox1 = std::min(b.max().x(), e.max().x());
      const double oy0 = std::max(b.min().y(), e.min().y()), oy1 = std::min(b.max().y(), e.max().y());
      const bool in_x = apart.x && c_P.x() > x0 && c_P.x() < x1 && c_P.y() > oy0 && c_P.y() < oy1;
      const bool in_y = apart.y && c_P.y() > y0 && c_P.y() < y1 && c_P.x() > ox0 && c_P.x() < ox1;
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
  TrialPlacement(const graph::SceneGraph& g, episode::WorldState& s, graph::PlatformId platform,
                 const Eigen::Vector2d& xy)
      : s_(s), platform_(platform), held_(s.held) {
    std::vector<graph::ObjectId> moving = {held_};
    for (const graph::PlatformId p : g.objects[held_].platforms) {
      for (const graph::ObjectId o : episode::everything_on(g, s, p)) moving.push_back(o);
    }
    for (const graph::ObjectId o : moving) {
      objects_.emplace_back(o, s.objects[o]);
      for (const graph::PlatformId p : g.objects[o].platforms) {
        offsets_.emplace_back(p, s.platform_offset[p]);
      }
    }
    episode::place_held(g, s, platform, xy);
  }
  ~TrialPlacement() {
    for (const auto& [o, state] : objects_) s_.objects[o] = state;
    for (const auto& [p, offset] : offsets_) s_.platform_offset[p] = offset;
    s_.children[platform_].pop_back();  // place_held appended the item
    s_.held = held_;
  }
  TrialPlacement(const TrialPlacement&) = delete;
  TrialPlacement& operator=(const TrialPlacement&) = delete;

 private:
  episode::WorldState& s_;
  graph::PlatformId platform_;
  graph::ObjectId held_;
  std::vector<std::pair<graph::ObjectId, episode::ObjectState>> objects_;
  std::vector<std::pair<graph::PlatformId, Eigen::Vector3d>> offsets_;
};

// Placement targets of each destination as the initial state offers them; shared (not copied)
// by every item that does not come from that destination (its obstacles are then the same).
// Items run in parallel, so the cache is shared under a lock; map nodes stay where they are, so
// a reference handed out stays valid.
class TargetCache {
 public:
  TargetCache(const graph::SceneGraph& g, const TaskOptions& options, episode::PlacementMemo* memo)
      : g_(g), options_(options), memo_(memo) {}

  std::vector<episode::PlaceTarget> build(const episode::WorldState& placing, graph::PlatformId pd, graph::Side side) const {
    std::vector<episode::PlaceTarget> t =
        episode::place_targets(g_, placing, pd, side, options_.rules.min_region_size, memo_);
    std::stable_partition(t.begin(), t.end(),
                          [](const episode::PlaceTarget& x) { return x.key == episode::kAnywhereKey; });
    episode::with_insets(t, memo_);
    return t;
  }
  episode::PlacementMemo* memo() const { return memo_; }
  const std::vector<episode::PlaceTarget>& shared(const episode::WorldState& placing, graph::PlatformId pd,
                                                 graph::Side side) {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto it = targets_.find(pd);
    if (it == targets_.end()) it = targets_.emplace(pd, build(placing, pd, side)).first;
    return it->second;
  }

 private:
  const graph::SceneGraph& g_;
  const TaskOptions& options_;
  episode::PlacementMemo* memo_;
  std::map<graph::PlatformId, std::vector<episode::PlaceTarget>> targets_;
  std::mutex mutex_;
};

// One item of the source list: the item picked up at its source.
struct Source {
  std::size_t src_label;  // the source's l-number - 1
  graph::ObjectId item;
  std::string pick_key;   // its o<N> there
};

// The tasks of one item (its goals over every destination), with what was left out and why.
class ItemEnumeration {
 public:
  ItemEnumeration(const graph::SceneGraph& g, const episode::WorldState& s, const TaskOptions& options,
                  const AtomicFilter& filter, TargetCache& cache, const Source& source)
      : g_(g), s_(s), options_(options), filter_(filter), cache_(cache), source_(source),
        ps_(g.navigable[source.src_label]), held_(s) {
    held_.at_platform = ps_;
    held_.side = g.platforms[ps_].default_side;
    held_.phase = episode::Phase::kAtPlatform;
    episode::pick(g, held_, source.item);
    const auto& o = held_.objects[source.item];
    own_height_ = o.top - o.bottom;
    carried_height_ = episode::stack_height(g, held_, source.item);
  }

  /// Every destination in label order; stops at the one goal a goal_key filter asks for.
  void run() {
    for (std::size_t dst_label = 0; dst_label < g_.navigable.size() && !found_asked_; ++dst_label) {
      const graph::PlatformId pd = g_.navigable[dst_label];
      if (filter_.destinations.empty() ||
          std::find(filter_.destinations.begin(), filter_.destinations.end(), pd) != filter_.destinations.end()) {
        destination(dst_label);
      }
    }
  }

  std::vector<AtomicTask>& tasks() { return out_; }
  /// Goals no key achieved robustly, by reason (per level, by look-alikes).
  DropCounts drops() const {
    DropCounts d;
    for (const auto& [key, why] : rejected_) {
      if (seen_.count(key) == 0) d.add(why.second, has_lookalikes(g_, s_, why.first, options_.ambiguity) ? 2 : 1);
    }
    return d;
  }

 private:
  // The item about to be put down on one destination: what every target there shares.
  struct Destination {
    // The item's state with the robot standing at the destination: held_ itself, not a copy per
    // destination (a whole world). Each destination sets where the robot stands; trial
    // placements put the objects back as they were.
    explicit Destination(episode::WorldState& held) : placing(held) {}
    episode::WorldState& placing;
    std::size_t dst_label = 0;
    graph::PlatformId pd;
    graph::Side side{};
    bool too_tall = false;  // with what rests on it: its goals are counted, never offered
    episode::FeasibleCentres feasible;
    std::vector<episode::PlaceTarget> own_targets;  // when the item came from here
    const std::vector<episode::PlaceTarget>* targets = nullptr;
    geom::Ring item_rel_P;
    Eigen::Isometry2d X_PW = Eigen::Isometry2d::Identity();
    std::vector<AnchorInfo> anchors;  // everything on the destination now, in its frame
    std::set<std::string> unbindable;  // around goals some of their anchor's own spaces miss
    AtomicGoal base;
  };
  // A goal a placement may achieve, with its key and margin.
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

  void destination(std::size_t dst_label) {
    Destination d(held_);
    d.dst_label = dst_label;
    d.pd = g_.navigable[dst_label];
    const graph::Platform& dest = g_.platforms[d.pd];
    if (own_height_ > dest.clearance) return;
    d.too_tall = carried_height_ > dest.clearance;
    d.placing.at_platform = d.pd;
    d.placing.side = dest.default_side;
    d.placing.phase = episode::Phase::kPlacing;
    d.side = static_cast<graph::Side>(dest.default_side);
    d.feasible = episode::held_feasible_centres(g_, d.placing, d.pd, cache_.memo());
    if (d.feasible.empty()) return;
    const bool from_here = episode::objects_on(d.placing, d.pd) != episode::objects_on(s_, d.pd);
    if (from_here) d.own_targets = cache_.build(d.placing, d.pd, d.side);
    d.targets = from_here ? &d.own_targets : &cache_.shared(d.placing, d.pd, d.side);
    d.item_rel_P = episode::held_footprint_P(g_, d.placing, d.pd);
    d.X_PW = episode::platform_frame(g_, d.placing, d.pd).inverse();
    for (const graph::ObjectId o : episode::objects_on(d.placing, d.pd)) {
      const geom::Ring& fp = d.placing.objects[o].footprint;
      d.anchors.push_back({o, geom::bounds(geom::transform(fp, d.X_PW)), &fp, geom::bounds(fp)});
    }
    if (filter_.anchor.valid() && std::none_of(d.anchors.begin(), d.anchors.end(),
                                            [&](const AnchorInfo& a) { return a.object == filter_.anchor; })) {
      return;
    }
    d.base.item = source_.item;
    d.base.source = ps_;
    d.base.platform = d.pd;
    // Every offered place judged first: "next to X" is asked only where each of X's own free
    // spaces meets it, since a person may pick any of them (issue 53).
    std::vector<std::pair<const episode::PlaceTarget*, std::pair<Eigen::Vector2d, Judged>>> judged_places;
    const auto concerns_anchor = anchor_places(d);
    for (const episode::PlaceTarget& t : *d.targets) {
      if (!concerns_anchor(t)) continue;
      const auto xy = episode::resolve_target(g_, d.placing, d.pd, t, d.feasible);
      if (!xy) continue;
      judged_places.push_back({&t, {*xy, judge_at(d, *xy)}});
    }
    d.unbindable.clear();
    // The goals a person binds through an object's own free spaces: next to X (any of X's), and
    // between X and Y (those of X facing Y, and of Y facing X). Each such space must meet them.
    std::map<std::string, const AtomicGoal*> bound_by_spaces;
    for (const auto& [t, placed] : judged_places) {
      for (const Candidate& c : placed.second.candidates) {
        const bool binds = c.goal.type == GoalType::kAround || c.goal.type == GoalType::kBetween;
        if (binds && c.margin > 0.0) bound_by_spaces.emplace(c.key, &c.goal);
      }
    }
    auto centre_of = [&](graph::ObjectId o) -> std::optional<geom::Point2> {
      for (const AnchorInfo& a : d.anchors) {
        if (a.object == o) return a.box_P.center();
      }
      return std::nullopt;
    };
    for (const auto& [t, placed] : judged_places) {
      if (t->kind != episode::PlaceTarget::Kind::kObjectRegion) continue;
      const auto& mine = placed.second.candidates;
      for (const auto& [key, goal] : bound_by_spaces) {
        if (goal->type == GoalType::kAround && goal->anchor != t->anchor) continue;
        if (goal->type == GoalType::kBetween) {
          if (goal->anchor != t->anchor && goal->anchor2 != t->anchor) continue;
          const auto here = centre_of(t->anchor);
          const auto there = centre_of(goal->anchor == t->anchor ? goal->anchor2 : goal->anchor);
          if (!here || !there || !faces(*t, *here, *there)) continue;
        }
        const bool met = std::any_of(mine.begin(), mine.end(),
                                     [&](const Candidate& m) { return m.key == key && m.margin > 0.0; });
        if (!met) d.unbindable.insert(key);
      }
    }
    for (auto& [t, placed] : judged_places) {
      for (Candidate& candidate : placed.second.candidates) {
        if (consider(d, *t, placed.first, placed.second, candidate)) return;
      }
    }
  }

  // Asked about one anchor (a step of a chain), a place gives a goal the task may ask only as one
  // of the anchor's own free spaces, as one of a neighbour it may be between with (whose own
  // spaces are checked against those goals), or inside the box of such a pair, where "between"
  // lies: a goal about the anchor from any other place is named by no words of the task, and
  // binds none (consider, the spaces' check above). Those places are not worked out. A place's
  // centre lies in its target's region (1 µm of rounding; 1 mm allowed).
  std::function<bool(const episode::PlaceTarget&)> anchor_places(const Destination& d) const {
    if (!filter_.anchor.valid()) return [](const episode::PlaceTarget&) { return true; };
    const auto anchor = std::find_if(d.anchors.begin(), d.anchors.end(),
                                     [&](const AnchorInfo& a) { return a.object == filter_.anchor; });
    std::vector<graph::ObjectId> concerned = {filter_.anchor};
    std::vector<Eigen::AlignedBox2d> pairs;
    for (const AnchorInfo& other : d.anchors) {
      if (other.object == filter_.anchor || !apart_of(anchor->box_P, other.box_P).between) continue;
      concerned.push_back(other.object);
      pairs.push_back(anchor->box_P.merged(other.box_P));
    }
    return [concerned = std::move(concerned), pairs = std::move(pairs)](const episode::PlaceTarget& t) {
      if (t.kind != episode::PlaceTarget::Kind::kObjectRegion) return true;
      if (std::find(concerned.begin(), concerned.end(), t.anchor) != concerned.end()) return true;
      Eigen::AlignedBox2d region = geom::bounds(t.region_P);
      region.min().array() -= 1e-3;
      region.max().array() += 1e-3;
      return std::any_of(pairs.begin(), pairs.end(), [&](const Eigen::AlignedBox2d& b) { return b.intersects(region); });
    };
  }

  // The goals a placement at xy may achieve, with their keys and margins, judged with the item
  // put down there; the item is back in hand when this returns.
  Judged judge_at(Destination& d, const Eigen::Vector2d& xy) const {
    Judged j;
    const TrialPlacement trial(g_, d.placing, d.pd, xy);
    const auto& moved = d.placing.objects[source_.item];
    j.c_P = d.X_PW * episode::footprint_centre(moved);
    j.placed_at = moved.position;
    std::vector<AtomicGoal> goals;
    if (d.pd != ps_) goals.push_back(d.base);  // the surface itself
    if (d.anchors.empty()) {
      for (int rel = 0; rel <= graph::kCentre; ++rel) {
        AtomicGoal part = d.base;
        part.type = GoalType::kSurfacePart;
        part.direction = rel;
        goals.push_back(part);
      }
    } else {
      candidate_goals(d.anchors, j.c_P, moved.footprint, geom::bounds(moved.footprint), d.side, options_, d.base, filter_.anchor, goals);
    }
    for (const AtomicGoal& goal : goals) {
      if (filter_.anchor.valid()) {  // the surface and its parts have no anchor
        const auto a = goal.anchors();
        if (std::find(a.begin(), a.end(), filter_.anchor) == a.end()) continue;
      }
      std::string key = goal_key(goal);
      if (!filter_.goal_key.empty() && key != filter_.goal_key) continue;
      const double margin = seen_.count(key) != 0 ? 0.0 : episode::goal_margin(g_, d.placing, goal, options_.goals);
      j.candidates.push_back({goal, std::move(key), margin});
    }
    return j;
  }

  // At least min_goal_area of centre positions meet the goal and fit. A disk of that area around
  // the placement, inside both, settles it without clipping polygons.
  bool roomy(const Destination& d, const AtomicGoal& goal, double margin, const geom::Point2& c_P) const {
    const double r = std::sqrt(options_.min_goal_area / std::numbers::pi);
    if (margin >= r && geom::contains(d.feasible.all, c_P) && geom::distance_to_boundary(d.feasible.all, c_P) >= r) {
      return true;
    }
    const geom::Region goal_P = episode::goal_region_P(g_, d.placing, goal, d.side, d.item_rel_P, options_.goals);
    return geom::area(geom::intersect(goal_P, d.feasible.all)) >= options_.min_goal_area;
  }

  // Keeps a candidate as a task when it is worth asking and robust, or notes why not; true when
  // it was the one goal a goal_key filter asks for.
  bool consider(const Destination& d, const episode::PlaceTarget& t, const Eigen::Vector2d& xy, const Judged& judged,
                Candidate& candidate) {
    const AtomicGoal& goal = candidate.goal;
    if (seen_.count(candidate.key) != 0) return false;
    const double margin = candidate.margin;
    if (margin <= 0.0) return false;  // not a goal of this placement: the judge decides
    const char* why = nullptr;
    // A direction is asked for only where the agent is offered it in the task's own words: the
    // free space of that side of that object ("front-right of object 3"), not a neighbour's
    // region that happens to reach there. "Next to the plate" likewise: a person picks one of the
    // plate's own free spaces, not the one of a neighbour that happens to lie close to it.
    const bool own_space = t.kind == episode::PlaceTarget::Kind::kObjectRegion && t.anchor == goal.anchor;
    const bool words_match = goal.type == GoalType::kDirection ? own_space && t.relative_dir == goal.direction
                             : goal.type == GoalType::kAround  ? own_space
                                                               : true;
    if (d.too_tall) {
      why = "stack";
    } else if (!words_match) {
      why = "unworded";
    } else if (d.unbindable.count(candidate.key) != 0) {
      why = "unbindable";
    } else if (episode::goal_met_from_any_side(g_, s_, goal, options_.goals)) {
      why = "trivial";
    } else if (margin < options_.min_margin) {
      why = "fragile";
    } else if (!roomy(d, goal, margin, judged.c_P)) {
      why = "small_area";
    }
    if (why != nullptr) {
      rejected_.emplace(candidate.key, std::make_pair(goal, why));  // another key may still achieve it
      return false;
    }
    seen_.insert(candidate.key);
    AtomicTask task;
    task.goal = goal;
    task.key = std::move(candidate.key);
    task.oracle = {graph::navigation_key(static_cast<int>(source_.src_label) + 1), source_.pick_key,
                   graph::navigation_key(static_cast<int>(d.dst_label) + 1), "startplace", t.key};
    task.place_xy = xy;
    task.placed_at = judged.placed_at;
    task.margin = margin;
    out_.push_back(std::move(task));
    found_asked_ = !filter_.goal_key.empty();  // the one goal asked for, where it is first achieved
    return found_asked_;
  }

  const graph::SceneGraph& g_;
  const episode::WorldState& s_;
  const TaskOptions& options_;
  const AtomicFilter& filter_;
  TargetCache& cache_;
  Source source_;
  graph::PlatformId ps_;
  episode::WorldState held_;
  double own_height_ = 0.0, carried_height_ = 0.0;
  std::set<std::string> seen_;
  std::map<std::string, std::pair<AtomicGoal, const char*>> rejected_;  // goal key -> why
  std::vector<AtomicTask> out_;
  bool found_asked_ = false;
};

}  // namespace

std::vector<AtomicTask> enumerate_atomic(const graph::SceneGraph& g, const episode::WorldState& s,
                                         const TaskOptions& options, const AtomicFilter& filter, DropCounts* dropped,
                                         int jobs, episode::PlacementMemo* memo) {
  MTG_DEMAND(dropped == nullptr || (filter.goal_key.empty() && !filter.anchor.valid()),
             "drop counts of a partial enumeration would be partial");
  // Every item to enumerate, in output order: source platforms by label, items in pickable_on's
  // order, each with its key there (the same order until something leaves or arrives).
  std::vector<Source> sources;
  for (std::size_t src_label = 0; src_label < g.navigable.size(); ++src_label) {
    const std::vector<graph::ObjectId> items = episode::pickable_on(g, s, g.navigable[src_label]);
    for (std::size_t k = 0; k < items.size(); ++k) {
      if (filter.items.empty() || std::find(filter.items.begin(), filter.items.end(), items[k]) != filter.items.end()) {
        sources.push_back({src_label, items[k], episode::object_key(g, s, items[k])});
      }
    }
  }
  struct Found {
    std::vector<AtomicTask> tasks;
    DropCounts dropped;
  };
  std::vector<Found> found(sources.size());
  TargetCache cache(g, options, memo);
  parallel_for(sources.size(), jobs, [&](std::size_t i) {
    ItemEnumeration item(g, s, options, filter, cache, sources[i]);
    item.run();
    found[i].tasks = std::move(item.tasks());
    if (dropped != nullptr) found[i].dropped = item.drops();
  });
  std::vector<AtomicTask> out;
  for (Found& f : found) {
    for (AtomicTask& t : f.tasks) out.push_back(std::move(t));
    if (dropped != nullptr) dropped->merge(f.dropped);
    if (!filter.goal_key.empty() && !out.empty()) break;  // a key names one item: at most one has it
  }
  return out;
}

bool faces(const episode::PlaceTarget& t, const geom::Point2& anchor_P, const geom::Point2& other_P) {
  const Eigen::Vector2d way = other_P - anchor_P;
  const Eigen::Vector2d aim = t.aim_P - anchor_P;
  if (way.norm() < 1e-9 || aim.norm() < 1e-9) return false;
  return way.normalized().dot(aim.normalized()) > std::cos(std::numbers::pi / 4.0);
}

void apply_effect(const graph::SceneGraph& g, episode::WorldState& s, const AtomicTask& task) {
  const graph::Platform& dest = g.platforms[task.goal.platform];
  episode::pick(g, s, task.goal.item);
  s.at_platform = task.goal.platform;
  s.side = dest.default_side;
  episode::place_held(g, s, task.goal.platform, task.place_xy);
  s.phase = episode::Phase::kAtPlatform;
  s.steps += static_cast<int>(task.oracle.size());
}

}  // namespace mtg::tasks
