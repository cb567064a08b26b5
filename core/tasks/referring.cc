#include "core/tasks/referring.h"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "core/episode/goals.h"
#include "core/episode/placement.h"
#include "core/graph/free_space.h"
#include "core/render/mark_layout.h"
#include "core/util/error.h"

namespace mtg::tasks {
namespace {

using episode::WorldState;

constexpr double kNextTo = 0.05;       // m between footprints: "next to"
constexpr double kNextToClear = 0.25;  // m: no other candidate this close to any landmark (nearer ones
                                       // look next to it in a picture seen at a slant)
constexpr double kOrdinalGap = 0.02;   // m between consecutive centres when counting along an axis
                                       // (and 10 image pixels in the picture, VisibilityOptions::min_gap)
constexpr double kRowGap = 0.03;       // m between two rows of look-alikes, front to back

// Relations tried, in order, with their rank (0: not an ordinal) and row.
struct Preferred {
  Relation relation;
  int rank;
  Row row;
};
constexpr Preferred kPreference[] = {
    {Relation::kOn, 0, Row::kNone},        {Relation::kUnder, 0, Row::kNone},     {Relation::kNextTo, 0, Row::kNone},
    {Relation::kFromLeft, 1, Row::kNone},  {Relation::kFromRight, 1, Row::kNone}, {Relation::kNearest, 1, Row::kNone},
    {Relation::kFarthest, 1, Row::kNone},  {Relation::kFromLeft, 2, Row::kNone},  {Relation::kFromRight, 2, Row::kNone},
    {Relation::kFromLeft, 3, Row::kNone},  {Relation::kFromRight, 3, Row::kNone}, {Relation::kFromLeft, 4, Row::kNone},
    {Relation::kFromRight, 4, Row::kNone}, {Relation::kFromLeft, 5, Row::kNone},  {Relation::kFromRight, 5, Row::kNone},
    // Look-alikes in two rows (a rack of spice jars): counted along one row.
    {Relation::kFromLeft, 1, Row::kFront}, {Relation::kFromRight, 1, Row::kFront},
    {Relation::kFromLeft, 1, Row::kBack},  {Relation::kFromRight, 1, Row::kBack},
    {Relation::kFromLeft, 2, Row::kFront}, {Relation::kFromRight, 2, Row::kFront},
    {Relation::kFromLeft, 2, Row::kBack},  {Relation::kFromRight, 2, Row::kBack},
    {Relation::kFromLeft, 3, Row::kFront}, {Relation::kFromRight, 3, Row::kFront},
    {Relation::kFromLeft, 3, Row::kBack},  {Relation::kFromRight, 3, Row::kBack},
    // Look-alikes in stacks (books lying on each other): counted from a stack's top or bottom.
    {Relation::kFromTop, 1, Row::kNone},   {Relation::kFromBottom, 1, Row::kNone},
    {Relation::kFromTop, 2, Row::kNone},   {Relation::kFromBottom, 2, Row::kNone},
    {Relation::kFromTop, 3, Row::kNone},   {Relation::kFromBottom, 3, Row::kNone}};
// Stacks among several, counted from the left (the stack field of a reference).
constexpr int kMaxStacks = 3;

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
  // Whether a person told `word` considers object k (its noun, or one the word covers).
  bool called(const std::string& word, std::size_t k) const { return g_.called(word, nouns_[k]); }
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
      if (k != i && called(landmark, k)) best = std::min(best, gap(i, k, limit));
    }
    return best;
  }

  // The indices a reference picks out (exactly one when it is good here).
  std::vector<std::size_t> resolve(const Reference& r) const {
    std::vector<std::size_t> candidates, out;
    for (std::size_t i = 0; i < size(); ++i) {
      if (called(r.noun, i)) candidates.push_back(i);
    }
    switch (r.relation) {
      case Relation::kAlone:
        return candidates;
      case Relation::kOn:
        for (const std::size_t c : candidates) {
          const int below = support(c);
          if (below >= 0 && called(r.landmark, static_cast<std::size_t>(below))) out.push_back(c);
        }
        return out;
      case Relation::kUnder:
        for (const std::size_t c : candidates) {
          const auto on = above(c);
          if (std::any_of(on.begin(), on.end(), [&](std::size_t k) { return called(r.landmark, k); })) {
            out.push_back(c);
          }
        }
        return out;
      case Relation::kNextTo:
        if (g_.called(r.landmark, r.noun) || g_.called(r.noun, r.landmark)) return candidates;  // never picks one out
        for (const std::size_t c : candidates) {
          if (gap_to(c, r.landmark, kNextToClear) <= kNextToClear) out.push_back(c);
        }
        // One candidate in the clear zone, and really next to its landmark.
        if (out.size() == 1 && gap_to(out.front(), r.landmark, kNextTo) > kNextTo) out.clear();
        return out;
      case Relation::kFromLeft: return counted(in_row(candidates, r.row), 2, r.rank);
      case Relation::kFromRight: return counted(in_row(candidates, r.row), 6, r.rank);
      case Relation::kNearest: return counted(candidates, 0, 1);
      case Relation::kFarthest: return counted(candidates, 4, 1);
      case Relation::kFromTop: return stacked(candidates, true, r.rank, r.stack, r.stack_from_right);
      case Relation::kFromBottom: return stacked(candidates, false, r.rank, r.stack, r.stack_from_right);
    }
    return out;
  }

  // Whether object `upper` rests, directly or through others, on object `lower`.
  bool rests_on(std::size_t upper, std::size_t lower) const {
    for (int k = support(upper); k >= 0; k = support(static_cast<std::size_t>(k))) {
      if (static_cast<std::size_t>(k) == lower) return true;
    }
    return false;
  }
  // A candidate with the candidates resting on it, bottom to top. A chain has them one on the
  // other (books lying on each other); a pile has two or more side by side somewhere above its
  // bottom (two books on one), so only its bottom is named by counting in it.
  struct Stack {
    std::vector<std::size_t> members;
    bool chain = true;
  };
  // The candidates' stacks, left to right as seen from the arrival side; a rack of jars standing
  // side by side is no stack. None when two stacks stand too close to tell which is left.
  std::vector<Stack> stacks_of(const std::vector<std::size_t>& candidates) const {
    std::map<std::size_t, std::vector<std::size_t>> by_base;
    for (const std::size_t c : candidates) {
      std::size_t base = c;  // the lowest candidate under it (itself when none)
      for (int k = support(c); k >= 0; k = support(static_cast<std::size_t>(k))) {
        if (std::find(candidates.begin(), candidates.end(), static_cast<std::size_t>(k)) != candidates.end()) {
          base = static_cast<std::size_t>(k);
        }
      }
      by_base[base].push_back(c);
    }
    std::vector<std::pair<double, Stack>> stacks;
    for (auto& [base, members] : by_base) {
      // The base first (every other member rests on it), the rest by height.
      std::sort(members.begin(), members.end(), [&, base = base](std::size_t a, std::size_t b) {
        if ((a == base) != (b == base)) return a == base;
        return s_.objects[objects_[a]].bottom < s_.objects[objects_[b]].bottom;
      });
      Stack stack{std::move(members), true};
      for (std::size_t k = 0; k + 1 < stack.members.size(); ++k) {
        stack.chain = stack.chain && rests_on(stack.members[k + 1], stack.members[k]);
      }
      stacks.emplace_back(-along(base, 2), std::move(stack));
    }
    std::sort(stacks.begin(), stacks.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Stack> out;
    for (std::size_t k = 0; k < stacks.size(); ++k) {
      if (k > 0 && stacks[k].first - stacks[k - 1].first < kOrdinalGap) return {};
      out.push_back(std::move(stacks[k].second));
    }
    return out;
  }
  // Which of `stacks` (left to right) a count names: "the stack" is the one stack of two or more
  // candidates; "the second stack from the right" counts from that end past stacks of two or
  // more only, since a person may count a lone candidate as a stack or not. None when unclear.
  static std::optional<std::size_t> stack_counted(const std::vector<Stack>& stacks, int stack, bool from_right) {
    if (stack <= 0) {
      std::optional<std::size_t> only;
      for (std::size_t k = 0; k < stacks.size(); ++k) {
        if (stacks[k].members.size() < 2) continue;
        if (only) return std::nullopt;
        only = k;
      }
      return only;
    }
    if (stack > static_cast<int>(stacks.size())) return std::nullopt;
    // The n-th stack (from 0) counted from the end the reference names.
    auto nth = [&](std::size_t n) { return from_right ? stacks.size() - 1 - n : n; };
    for (std::size_t n = 0; n + 1 < static_cast<std::size_t>(stack); ++n) {
      if (stacks[nth(n)].members.size() < 2) return std::nullopt;
    }
    return nth(static_cast<std::size_t>(stack) - 1);
  }
  // Counting candidates down (or up) a stack of at least two candidates: the only such stack
  // (`stack` 0), or the `stack`-th of several from the left (or right).
  std::vector<std::size_t> stacked(const std::vector<std::size_t>& candidates, bool from_top, int rank, int stack,
                                   bool from_right) const {
    if (candidates.size() < 2 || rank < 1) return {};
    const std::vector<Stack> stacks = stacks_of(candidates);
    if (stacks.empty()) return candidates;  // no telling the stacks apart
    const std::optional<std::size_t> at = stack_counted(stacks, stack, from_right);
    if (!at) return candidates;
    const Stack& counted = stacks[*at];
    std::vector<std::size_t> chain = counted.members;
    if (chain.size() < 2 || rank > static_cast<int>(chain.size())) return {};
    // In a pile only the bottom is one: above it, some stand side by side.
    if (!counted.chain && (from_top || rank > 1)) return chain;
    if (from_top) std::reverse(chain.begin(), chain.end());
    return {chain[static_cast<std::size_t>(rank) - 1]};
  }

  // The candidates of one row when they stand in two rows, front to back, at least kRowGap apart
  // with each row narrower than that gap; none when they do not (or for Row::kNone, all).
  std::vector<std::size_t> in_row(const std::vector<std::size_t>& candidates, Row row) const {
    if (row == Row::kNone) return candidates;
    const std::array<std::vector<std::size_t>, 2> rows = rows_of(candidates);
    return rows[row == Row::kFront ? 0 : 1];
  }
  std::array<std::vector<std::size_t>, 2> rows_of(const std::vector<std::size_t>& candidates) const {
    std::vector<std::pair<double, std::size_t>> depth;  // farther is larger
    for (const std::size_t c : candidates) depth.emplace_back(along(c, 4), c);
    std::sort(depth.begin(), depth.end());
    if (depth.size() < 2) return {};
    std::size_t cut = 0;
    double widest = -1.0;
    for (std::size_t k = 0; k + 1 < depth.size(); ++k) {
      const double gap = depth[k + 1].first - depth[k].first;
      if (gap > widest) {
        widest = gap;
        cut = k + 1;
      }
    }
    const double front_spread = depth[cut - 1].first - depth.front().first;
    const double back_spread = depth.back().first - depth[cut].first;
    if (widest < kRowGap || front_spread >= widest || back_spread >= widest) return {};
    std::array<std::vector<std::size_t>, 2> out;
    for (std::size_t k = 0; k < depth.size(); ++k) out[k < cut ? 0 : 1].push_back(depth[k].second);
    std::sort(out[0].begin(), out[0].end());
    std::sort(out[1].begin(), out[1].end());
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
        return std::any_of(on.begin(), on.end(), [&](std::size_t k) { return called(r.landmark, k) && visible(k); });
      }
      case Relation::kNextTo:
        for (std::size_t k = 0; k < size(); ++k) {
          if (k != i && called(r.landmark, k) && gap(i, k, kNextTo) <= kNextTo && visible(k)) return true;
        }
        return false;
      case Relation::kFromLeft: return counted_in_view(r.noun, 2, r.rank, r.row);
      case Relation::kFromRight: return counted_in_view(r.noun, 6, r.rank, r.row);
      case Relation::kNearest: return counted_in_view(r.noun, 0, 1, Row::kNone);
      case Relation::kFarthest: return counted_in_view(r.noun, 4, 1, Row::kNone);
      case Relation::kFromTop: return stacked_in_view(r.noun, true, r.rank, r.stack, r.stack_from_right);
      case Relation::kFromBottom: return stacked_in_view(r.noun, false, r.rank, r.stack, r.stack_from_right);
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
        if (k != i && !called(nouns_[k], i) && !called(nouns_[i], k) && gap(i, k, kNextTo) <= kNextTo) out.insert(nouns_[k]);
      }
    }
    return {out.begin(), out.end()};
  }

 private:
  // Whether a person counting the candidates called `noun` along a viewer axis counts as the
  // footprints do, in one of the view's pictures: the candidates up to the `rank`-th clearly
  // visible there, the picture's order of all of them the footprints' order (one that shows less
  // still stands where it stands), and each of the first `rank` at least min_gap pixels from the
  // next. Left/right read along the image's width at mid-height; near/far along its height at
  // the bottom (nearer stands lower in the picture).
  // Counting in a row, the two rows must show as rows too: every candidate of the near row lower
  // in the picture than every one of the far row, by min_gap pixels.
  bool counted_in_view(const std::string& noun, int relative_dir, int rank, Row row) const {
    std::vector<std::size_t> candidates;
    for (std::size_t i = 0; i < size(); ++i) {
      if (called(noun, i)) candidates.push_back(i);
    }
    const std::array<std::vector<std::size_t>, 2> rows =
        row == Row::kNone ? std::array<std::vector<std::size_t>, 2>{} : rows_of(candidates);
    // A stack counts as its bottom, and its every member must stand past the one counted in the
    // picture too (counted above).
    const StackSplit split = split_stacks(row == Row::kNone ? candidates : rows[row == Row::kFront ? 0 : 1]);
    std::vector<std::pair<double, std::size_t>> order;
    for (const std::size_t i : split.counted) order.emplace_back(-along(i, relative_dir), i);
    std::sort(order.begin(), order.end());
    for (std::size_t k = 0; k < sight_->pictures(); ++k) {
      if (!counted_in_picture(order, k, relative_dir, rank)) continue;
      if (!split.stacked.empty() && !stacks_past_in_picture(order, split.stacked, k, relative_dir, rank)) continue;
      if (row == Row::kNone || rows_apart_in_picture(rows, k)) return true;
    }
    return false;
  }

  // Counting down (or up) a stack in a picture: the candidates up to the counted one clearly
  // visible there, each standing at least min_gap pixels above (below) the next; counting several
  // stacks, their bottoms in the picture's order from the end counted from as min_gap apart.
  bool stacked_in_view(const std::string& noun, bool from_top, int rank, int stack, bool from_right) const {
    std::vector<std::size_t> candidates;
    for (std::size_t i = 0; i < size(); ++i) {
      if (called(noun, i)) candidates.push_back(i);
    }
    const std::vector<Stack> stacks = stacks_of(candidates);
    const std::optional<std::size_t> counted_at = stack_counted(stacks, stack, from_right);
    if (!counted_at) return false;
    const Stack& counted = stacks[*counted_at];
    std::vector<std::size_t> chain = counted.members;
    if (from_top) std::reverse(chain.begin(), chain.end());
    std::vector<std::pair<double, std::size_t>> order;
    for (const std::size_t i : chain) order.emplace_back(0.0, i);
    std::vector<std::pair<double, std::size_t>> bases;
    for (const auto& st : stacks) bases.emplace_back(0.0, st.members.front());
    if (from_right) std::reverse(bases.begin(), bases.end());
    for (std::size_t k = 0; k < sight_->pictures(); ++k) {
      bool ok = true;
      std::vector<double> at;  // image y, growing along the count
      for (std::size_t n = 0; n < order.size() && ok; ++n) {
        const std::size_t i = order[n].second;
        if (static_cast<int>(n) < rank && !sight_->clearly_visible_in(k, objects_[i])) ok = false;
        const auto px = sight_->camera(k).project(centre_3d(i));
        if (!px) ok = false;
        if (ok) at.push_back(from_top ? px->y() : -px->y());
      }
      const double gap = ok ? gap_in(k, order, rank) : 0.0;
      for (std::size_t n = 0; ok && n + 1 < at.size(); ++n) {
        if (counted.chain) {
          if (at[n + 1] - at[n] < (static_cast<int>(n) < rank ? gap : 0.0)) ok = false;
        } else if (at[n + 1] - at.front() < gap) {
          ok = false;  // a pile's bottom lies below each of the others, side by side in no order
        }
      }
      // Which stack is which: counted from the left up to the one meant.
      if (ok && stack > 0) ok = counted_in_picture(bases, k, from_right ? 6 : 2, stack);
      if (ok) return true;
    }
    return false;
  }

  bool rows_apart_in_picture(const std::array<std::vector<std::size_t>, 2>& rows, std::size_t picture) const {
    double front_top = std::numeric_limits<double>::infinity();  // image y grows downwards
    double back_bottom = -std::numeric_limits<double>::infinity();
    for (int r = 0; r < 2; ++r) {
      for (const std::size_t i : rows[static_cast<std::size_t>(r)]) {
        const auto px = sight_->camera(picture).project(
            Eigen::Vector3d(centres_W_[i].x(), centres_W_[i].y(), s_.objects[objects_[i]].bottom));
        if (!px) return false;
        if (r == 0) front_top = std::min(front_top, px->y());
        if (r == 1) back_bottom = std::max(back_bottom, px->y());
      }
    }
    std::vector<std::pair<double, std::size_t>> all;
    for (const auto& row : rows) {
      for (const std::size_t i : row) all.emplace_back(0.0, i);
    }
    return front_top - back_bottom >= gap_in(picture, all, static_cast<int>(all.size()));
  }

  // The pixels a person needs between counted neighbours in picture k: min_gap, or half of it
  // where every one counted (the first rank + 1 of `order`) shows under the size the renderer
  // zooms at least twice as big (mark_layout.h, kSmallShare): the person counts in the zoom.
  double gap_in(std::size_t k, const std::vector<std::pair<double, std::size_t>>& order, int rank) const {
    const render::Camera& camera = sight_->camera(k);
    const double small = render::kSmallShare * camera.width * camera.height;
    for (std::size_t n = 0; n < order.size() && static_cast<int>(n) <= rank; ++n) {
      if (sight_->image_pixels_in(k, objects_[order[n].second]) >= small) return min_gap_;
    }
    return min_gap_ / 2.0;
  }

  bool counted_in_picture(const std::vector<std::pair<double, std::size_t>>& order, std::size_t picture,
                          int relative_dir, int rank) const {
    const bool sideways = relative_dir == 2 || relative_dir == 6;
    // Image coordinate growing along the counting direction.
    std::vector<double> at;
    for (std::size_t n = 0; n < order.size(); ++n) {
      const std::size_t i = order[n].second;
      if (static_cast<int>(n) < rank && !sight_->clearly_visible_in(picture, objects_[i])) return false;
      // Sideways at mid-height; near/far at the foot (nearer stands lower in the picture).
      const Eigen::Vector3d p =
          sideways ? centre_3d(i) : Eigen::Vector3d(centres_W_[i].x(), centres_W_[i].y(), s_.objects[objects_[i]].bottom);
      const auto px = sight_->camera(picture).project(p);
      if (!px) return false;
      const double coordinate = sideways ? px->x() : px->y();
      at.push_back(relative_dir == 2 || relative_dir == 4 ? coordinate : -coordinate);
    }
    const double gap = gap_in(picture, order, rank);
    for (std::size_t k = 0; k + 1 < at.size(); ++k) {
      const double step = at[k + 1] - at[k];
      if (step < (static_cast<int>(k) < rank ? gap : 0.0)) return false;
    }
    // Left and right are read side by side: two lamps one behind the other from this side are
    // "the near lamp" and "the far lamp", not a leftmost and a rightmost, even when their centres
    // differ by a few pixels. Each counted neighbour stands at most twice as far behind (or in
    // front of) the next as beside it, seen from the camera.
    if (sideways) {
      const Eigen::Isometry3d X_CW = sight_->camera(picture).X_WC.inverse();
      for (std::size_t k = 0; k + 1 < order.size() && static_cast<int>(k) < rank; ++k) {
        const Eigen::Vector3d a = X_CW * centre_3d(order[k].second), b = X_CW * centre_3d(order[k + 1].second);
        if (std::abs(b.z() - a.z()) > 2.0 * std::abs(b.x() - a.x())) return false;  // the camera looks along -z
      }
    }
    return true;
  }

  // Whether every stack member stands past the counted one (order[rank - 1]) in picture k, by
  // the gap the count asks for.
  bool stacks_past_in_picture(const std::vector<std::pair<double, std::size_t>>& order,
                              const std::vector<std::size_t>& stacked, std::size_t picture, int relative_dir,
                              int rank) const {
    if (rank < 1 || rank > static_cast<int>(order.size())) return false;
    const bool sideways = relative_dir == 2 || relative_dir == 6;
    auto coordinate = [&](std::size_t i) -> std::optional<double> {
      const Eigen::Vector3d p =
          sideways ? centre_3d(i) : Eigen::Vector3d(centres_W_[i].x(), centres_W_[i].y(), s_.objects[objects_[i]].bottom);
      const auto px = sight_->camera(picture).project(p);
      if (!px) return std::nullopt;
      const double c = sideways ? px->x() : px->y();
      return relative_dir == 2 || relative_dir == 4 ? c : -c;
    };
    const auto at = coordinate(order[static_cast<std::size_t>(rank) - 1].second);
    if (!at) return false;
    const double gap = gap_in(picture, order, rank);
    for (const std::size_t m : stacked) {
      const auto c = coordinate(m);
      if (!c || *c - *at < gap) return false;
    }
    return true;
  }

  // Candidate i's footprint centre at mid-height, in the world.
  Eigen::Vector3d centre_3d(std::size_t i) const {
    const episode::ObjectState& o = s_.objects[objects_[i]];
    return {centres_W_[i].x(), centres_W_[i].y(), (o.bottom + o.top) / 2.0};
  }

  // Counting candidates along a viewer axis from its far end: the rank-th one, when it and every
  // one before it stand at least kOrdinalGap from the next; else the pair too close to tell
  // apart (the reference is ambiguous).
  std::vector<std::size_t> counted(const std::vector<std::size_t>& candidates, int relative_dir, int rank) const {
    // One of them on another (a book on a book): a person may count the stack once or book by
    // book, so a count is clear only up to the first stack. Past it the stack relations name
    // them; before it, counting reads the same either way ("the leftmost book" beside a pile
    // further right), so the pile counts as its bottom, and all of it must lie past the one
    // counted, by the ordinal gap.
    const StackSplit split = split_stacks(candidates);
    std::vector<std::pair<double, std::size_t>> order;
    for (const std::size_t c : split.counted) order.emplace_back(-along(c, relative_dir), c);
    std::sort(order.begin(), order.end());
    if (rank < 1 || rank > static_cast<int>(order.size())) return {};
    for (std::size_t i = 0; i < static_cast<std::size_t>(rank) && i + 1 < order.size(); ++i) {
      if (order[i + 1].first - order[i].first < kOrdinalGap) return {order[i].second, order[i + 1].second};
    }
    const auto& [at, meant] = order[static_cast<std::size_t>(rank) - 1];
    for (const std::size_t m : split.stacked) {
      if (-along(m, relative_dir) < at + kOrdinalGap) return candidates;
    }
    return {meant};
  }

  // The candidates of a count: those resting on no other candidate (a stack's bottom stands for
  // it), and every member of a stack (bottoms included).
  struct StackSplit {
    std::vector<std::size_t> counted;
    std::vector<std::size_t> stacked;
  };
  StackSplit split_stacks(const std::vector<std::size_t>& candidates) const {
    StackSplit out;
    for (const std::size_t a : candidates) {
      bool on_another = false, carries = false;
      for (const std::size_t b : candidates) {
        if (a == b) continue;
        on_another = on_another || rests_on(a, b);
        carries = carries || rests_on(b, a);
      }
      if (!on_another) out.counted.push_back(a);
      if (on_another || carries) out.stacked.push_back(a);
    }
    return out;
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
    same += g.called(noun, noun_of(g.objects[o], rule)) ? 1 : 0;
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
  for (const auto& [relation, rank, row] : kPreference) {
    r.relation = relation;
    r.rank = rank;
    r.row = row;
    r.stack = 0;
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
  // Stacks among several: "the book at the top of the leftmost stack", "... the rightmost stack".
  for (int stack = 1; stack <= kMaxStacks; ++stack) {
    for (const bool from_right : {false, true}) {
      for (const auto& [relation, rank, row] : kPreference) {
        if (relation != Relation::kFromTop && relation != Relation::kFromBottom) continue;
        r = Reference{relation, r.noun, "", rank, Row::kNone, stack, from_right};
        if (names_it(r)) return found(r);
      }
    }
  }
  return out;
}

}  // namespace mtg::tasks
