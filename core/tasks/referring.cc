#include "core/tasks/referring.h"

#include <algorithm>
#include <limits>
#include <memory>
#include <set>

#include "core/episode/goals.h"
#include "core/episode/placement.h"
#include "core/graph/free_space.h"
#include "core/util/error.h"

namespace mtg::tasks {
namespace {

using episode::WorldState;

constexpr double kNextTo = 0.05;       // m between footprints: "next to"
constexpr double kNextToClear = 0.15;  // m: no other candidate this close to any landmark
constexpr double kOrdinalGap = 0.03;   // m between consecutive centres when counting along an axis

// Relations tried, in order, with their rank (0: not an ordinal).
constexpr std::pair<Relation, int> kPreference[] = {
    {Relation::kOn, 0},        {Relation::kUnder, 0},    {Relation::kNextTo, 0},    {Relation::kFromLeft, 1},
    {Relation::kFromRight, 1}, {Relation::kNearest, 1},  {Relation::kFarthest, 1},  {Relation::kFromLeft, 2},
    {Relation::kFromRight, 2}, {Relation::kFromLeft, 3}, {Relation::kFromRight, 3}, {Relation::kFromLeft, 4},
    {Relation::kFromRight, 4}};

// One platform as a reader of references sees it in one state: everything on it (at any depth),
// what each is called, and where each stands as seen from the arrival side.
class PlatformView {
 public:
  PlatformView(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform, Ambiguity rule,
               const render::VisibilityOracle* seeing = nullptr)
      : g_(g), s_(s), platform_(platform), objects_(episode::everything_on(g, s, platform)), seeing_(seeing) {
    if (seeing != nullptr) min_gap_ = seeing->options().min_gap;
    const graph::Platform& p = g.platforms[platform];
    side_ = static_cast<graph::Side>(std::max(0, p.default_side));
    const Eigen::Isometry2d X_PW = episode::platform_frame(g, s, platform).inverse();
    for (const graph::ObjectId o : objects_) {
      nouns_.push_back(noun_of(g.objects[o], rule));
      centres_W_.push_back(episode::footprint_centre(s.objects[o]));
      centres_P_.push_back(X_PW * centres_W_.back());
      boxes_W_.push_back(geom::bounds(s.objects[o].footprint));
    }
  }
  // A view of the platform whose arrival view is `sight` (an independent id pass, for audits).
  PlatformView(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform, Ambiguity rule,
               std::shared_ptr<const render::ViewSight> sight, double min_gap)
      : PlatformView(g, s, platform, rule) {
    sight_ = std::move(sight);
    min_gap_ = min_gap;
  }

  std::size_t size() const { return objects_.size(); }
  graph::ObjectId object(std::size_t i) const { return objects_[i]; }
  const std::string& noun(std::size_t i) const { return nouns_[i]; }
  // The index of an object, or -1 when it is not on the platform.
  int index_of(graph::ObjectId object) const {
    const auto it = std::find(objects_.begin(), objects_.end(), object);
    return it == objects_.end() ? -1 : static_cast<int>(it - objects_.begin());
  }
  // Coordinate along a robot-relative direction (2 left, 6 right, 0 near, 4 far).
  double along(std::size_t i, int relative_dir) const {
    const Eigen::Vector2i step = graph::direction_step(graph::platform_direction(relative_dir, side_));
    return centres_P_[i].dot(Eigen::Vector2d(step.x(), step.y()));
  }
  // The view position of the object it rests on, or -1 when it stands on the platform itself.
  int support(std::size_t i) const {
    const graph::PlatformId p = s_.objects[objects_[i]].parent;
    return p == platform_ || !p.valid() ? -1 : index_of(g_.platforms[p].owner);
  }
  // Indices of the objects resting directly on object i.
  std::vector<std::size_t> above(std::size_t i) const {
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < size(); ++k) {
      if (support(k) == static_cast<int>(i)) out.push_back(k);
    }
    return out;
  }
  // The gap between objects i and k where it is at most `limit`; beyond, some distance above it
  // (episode::footprint_gap_up_to): the relations only compare gaps with their limits.
  double gap(std::size_t i, std::size_t k, double limit) const {
    return episode::footprint_gap_up_to(s_.objects[objects_[i]].footprint, boxes_W_[i],
                                        s_.objects[objects_[k]].footprint, boxes_W_[k], limit);
  }
  // Smallest gap from object i to any object called `landmark` (other than itself), exact where
  // it is at most `limit`.
  double gap_to(std::size_t i, const std::string& landmark, double limit) const {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < size(); ++k) {
      if (k != i && nouns_[k] == landmark) best = std::min(best, gap(i, k, limit));
    }
    return best;
  }

  // The indices a reference picks out (exactly one when it is good here).
  std::vector<std::size_t> resolve(const Reference& r) const {
    std::vector<std::size_t> candidates, out;
    for (std::size_t i = 0; i < size(); ++i) {
      if (nouns_[i] == r.noun) candidates.push_back(i);
    }
    switch (r.relation) {
      case Relation::kAlone:
        return candidates;
      case Relation::kOn:
        for (const std::size_t c : candidates) {
          const int below = support(c);
          if (below >= 0 && nouns_[static_cast<std::size_t>(below)] == r.landmark) out.push_back(c);
        }
        return out;
      case Relation::kUnder:
        for (const std::size_t c : candidates) {
          const auto on = above(c);
          if (std::any_of(on.begin(), on.end(), [&](std::size_t k) { return nouns_[k] == r.landmark; })) {
            out.push_back(c);
          }
        }
        return out;
      case Relation::kNextTo:
        if (r.landmark == r.noun) return candidates;  // symmetric: never picks one out
        for (const std::size_t c : candidates) {
          if (gap_to(c, r.landmark, kNextToClear) <= kNextToClear) out.push_back(c);
        }
        // One candidate in the clear zone, and really next to its landmark.
        if (out.size() == 1 && gap_to(out.front(), r.landmark, kNextTo) > kNextTo) out.clear();
        return out;
      case Relation::kFromLeft: return counted(candidates, 2, r.rank);
      case Relation::kFromRight: return counted(candidates, 6, r.rank);
      case Relation::kNearest: return counted(candidates, 0, 1);
      case Relation::kFarthest: return counted(candidates, 4, 1);
    }
    return out;
  }

  // Whether the arrival view shows what reference `r` to object i needs (referring.h); always
  // when there is no view to ask.
  bool seen(const Reference& r, std::size_t i) const {
    if (seeing_ == nullptr && !sight_) return true;
    // Drawn only when a reference names the object in the geometry: most never do.
    if (!sight_) sight_ = seeing_->arrival_view(s_, platform_);
    auto visible = [&](std::size_t k) { return sight_->clearly_visible(objects_[k]); };
    if (!visible(i)) return false;
    switch (r.relation) {
      case Relation::kAlone: return true;
      case Relation::kOn: {
        const int below = support(i);
        return below >= 0 && visible(static_cast<std::size_t>(below));
      }
      case Relation::kUnder: {
        const auto on = above(i);
        return std::any_of(on.begin(), on.end(), [&](std::size_t k) { return nouns_[k] == r.landmark && visible(k); });
      }
      case Relation::kNextTo:
        for (std::size_t k = 0; k < size(); ++k) {
          if (k != i && nouns_[k] == r.landmark && gap(i, k, kNextTo) <= kNextTo && visible(k)) return true;
        }
        return false;
      case Relation::kFromLeft: return counted_in_view(r.noun, 2, r.rank);
      case Relation::kFromRight: return counted_in_view(r.noun, 6, r.rank);
      case Relation::kNearest: return counted_in_view(r.noun, 0, 1);
      case Relation::kFarthest: return counted_in_view(r.noun, 4, 1);
    }
    return false;
  }

  // Landmark nouns worth trying for object i under relation r, in a fixed order.
  std::vector<std::string> landmarks_for(std::size_t i, Relation r) const {
    std::set<std::string> out;
    if (r == Relation::kOn) {
      if (support(i) >= 0) out.insert(nouns_[static_cast<std::size_t>(support(i))]);
    } else if (r == Relation::kUnder) {
      for (const std::size_t k : above(i)) out.insert(nouns_[k]);
    } else if (r == Relation::kNextTo) {
      for (std::size_t k = 0; k < size(); ++k) {
        if (k != i && nouns_[k] != nouns_[i] && gap(i, k, kNextTo) <= kNextTo) out.insert(nouns_[k]);
      }
    }
    return {out.begin(), out.end()};
  }

 private:
  // Whether a person counting the candidates called `noun` along a viewer axis in the picture
  // counts as the footprints do: every candidate clearly visible, the picture's order the
  // footprints' order, and each of the first `rank` neighbours at least min_gap pixels from the
  // next. Left/right read along the image's width at mid-height; near/far along its height at
  // the bottom (nearer stands lower in the picture).
  bool counted_in_view(const std::string& noun, int relative_dir, int rank) const {
    std::vector<std::pair<double, std::size_t>> order;
    for (std::size_t i = 0; i < size(); ++i) {
      if (nouns_[i] != noun) continue;
      if (!sight_->clearly_visible(objects_[i])) return false;
      order.emplace_back(-along(i, relative_dir), i);
    }
    std::sort(order.begin(), order.end());
    const bool sideways = relative_dir == 2 || relative_dir == 6;
    // Image coordinate growing along the counting direction.
    std::vector<double> at;
    for (const auto& [key, i] : order) {
      const episode::ObjectState& o = s_.objects[objects_[i]];
      const double z = sideways ? (o.bottom + o.top) / 2.0 : o.bottom;
      const auto px = sight_->camera().project(Eigen::Vector3d(centres_W_[i].x(), centres_W_[i].y(), z));
      if (!px) return false;
      const double coordinate = sideways ? px->x() : px->y();
      at.push_back(relative_dir == 2 || relative_dir == 4 ? coordinate : -coordinate);
    }
    for (std::size_t k = 0; k + 1 < at.size(); ++k) {
      const double step = at[k + 1] - at[k];
      if (step < (static_cast<int>(k) < rank ? min_gap_ : 0.0)) return false;
    }
    return true;
  }

  // Counting candidates along a viewer axis from its far end: the rank-th one, when it and every
  // one before it stand at least kOrdinalGap from the next; else the pair too close to tell
  // apart (the reference is ambiguous).
  std::vector<std::size_t> counted(const std::vector<std::size_t>& candidates, int relative_dir, int rank) const {
    std::vector<std::pair<double, std::size_t>> order;
    for (const std::size_t c : candidates) order.emplace_back(-along(c, relative_dir), c);
    std::sort(order.begin(), order.end());
    if (rank < 1 || rank > static_cast<int>(order.size())) return {};
    for (std::size_t i = 0; i < static_cast<std::size_t>(rank) && i + 1 < order.size(); ++i) {
      if (order[i + 1].first - order[i].first < kOrdinalGap) return {order[i].second, order[i + 1].second};
    }
    return {order[static_cast<std::size_t>(rank) - 1].second};
  }

  const graph::SceneGraph& g_;
  const WorldState& s_;
  graph::PlatformId platform_;
  graph::Side side_ = graph::Side::kRear;
  std::vector<graph::ObjectId> objects_;
  std::vector<std::string> nouns_;
  std::vector<geom::Point2> centres_P_;
  std::vector<geom::Point2> centres_W_;
  const render::VisibilityOracle* seeing_;
  mutable std::shared_ptr<const render::ViewSight> sight_;  // the arrival view, once asked for
  double min_gap_ = 0.0;
  std::vector<Eigen::AlignedBox2d> boxes_W_;  // the footprints' boxes
};

}  // namespace

std::string noun_of(const graph::GraphObject& o, Ambiguity rule) {
  if (rule == Ambiguity::kNoun && !o.noun.empty()) return o.noun;
  if ((rule == Ambiguity::kCategory || rule == Ambiguity::kNoun) && !o.category.empty()) {
    std::string noun = o.category;
    std::replace(noun.begin(), noun.end(), '_', ' ');
    return noun;
  }
  return episode::display_name(o);
}

std::vector<graph::ObjectId> resolve(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform,
                                     const Reference& r, Ambiguity rule) {
  const PlatformView view(g, s, platform, rule);
  std::vector<graph::ObjectId> out;
  for (const std::size_t i : view.resolve(r)) out.push_back(view.object(i));
  return out;
}

bool has_lookalike(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object, graph::PlatformId platform,
                   Ambiguity rule) {
  const std::string noun = noun_of(g.objects[object], rule);
  int same = 0;
  for (const graph::ObjectId o : episode::everything_on(g, s, platform)) {
    same += noun_of(g.objects[o], rule) == noun ? 1 : 0;
  }
  return same > 1;
}

bool seen_as(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform, graph::ObjectId object,
             const Reference& r, Ambiguity rule, std::shared_ptr<const render::ViewSight> sight, double min_gap) {
  const PlatformView view(g, s, platform, rule, std::move(sight), min_gap);
  const int i = view.index_of(object);
  return i >= 0 && view.seen(r, static_cast<std::size_t>(i));
}

Referral refer(const graph::SceneGraph& g, const std::vector<const WorldState*>& states, graph::ObjectId object,
               graph::PlatformId platform, Ambiguity rule, const render::VisibilityOracle* seeing) {
  MTG_DEMAND(!states.empty(), "refer() needs a state");
  std::vector<PlatformView> views;
  for (const WorldState* s : states) views.emplace_back(g, *s, platform, rule, seeing);
  Referral out;
  const int first = views.front().index_of(object);
  if (first < 0) return out;  // not on that platform
  // The reference names it in the geometry; then whether every view shows what it needs.
  auto names_it = [&](const Reference& r) {
    const bool named = std::all_of(views.begin(), views.end(), [&](const PlatformView& v) {
      const std::vector<std::size_t> found = v.resolve(r);
      return found.size() == 1 && v.object(found.front()) == object;
    });
    if (!named) return false;
    out.occluded = true;
    return std::all_of(views.begin(), views.end(), [&](const PlatformView& v) {
      return v.seen(r, static_cast<std::size_t>(v.index_of(object)));
    });
  };
  Reference r;
  r.noun = views.front().noun(static_cast<std::size_t>(first));
  auto found = [&](const Reference& ref) {
    out.reference = ref;
    out.occluded = false;
    return out;
  };
  if (names_it(r)) return found(r);
  for (const auto& [relation, rank] : kPreference) {
    r.relation = relation;
    r.rank = rank;
    r.landmark.clear();
    if (!needs_landmark(relation)) {
      if (names_it(r)) return found(r);
      continue;
    }
    for (const std::string& landmark : views.front().landmarks_for(static_cast<std::size_t>(first), relation)) {
      r.landmark = landmark;
      if (names_it(r)) return found(r);
    }
  }
  return out;
}

}  // namespace mtg::tasks
