#include "core/tasks/reference_memo.h"

#include <string>

#include "core/util/error.h"

namespace mtg::tasks {

Referral refer_in(const graph::SceneGraph& g, const episode::WorldState& s, graph::ObjectId object,
                  graph::PlatformId platform, graph::ObjectId held_item, Ambiguity rule,
                  const render::VisibilityOracle* seeing) {
  if (!held_item.valid()) return refer(g, {&s}, object, platform, rule, seeing);
  episode::WorldState held = s;
  episode::pick(g, held, held_item);
  return refer(g, {&s, &held}, object, platform, rule, seeing);
}

ReferenceMemo::ReferenceMemo(const graph::SceneGraph& g, const episode::WorldState& base, Ambiguity rule,
                             const render::VisibilityOracle* seeing)
    : g_(g), base_(base), rule_(rule), seeing_(seeing) {
  if (seeing_ == nullptr) return;
  base_views_.resize(g.platforms.size());
  for (const graph::PlatformId p : g.navigable) base_views_[p.index()] = seeing_->view_key(base_, p);
}

bool ReferenceMemo::as_in_base(const episode::WorldState& s, graph::PlatformId platform) const {
  if (&s == &base_) return true;
  // What a view of the platform reads (referring.cc, PlatformView): its frame, everything on it
  // in order, and each object's footprint and support. Picking an item changes only these.
  if (s.platform_offset.at(platform) != base_.platform_offset.at(platform)) return false;
  const std::vector<graph::ObjectId> here = episode::everything_on(g_, s, platform);
  if (here != episode::everything_on(g_, base_, platform)) return false;
  for (const graph::ObjectId o : here) {
    const episode::ObjectState &now = s.objects[o], &then = base_.objects[o];
    if (now.parent != then.parent || now.footprint != then.footprint) return false;
  }
  // What the arrival view shows may change with items on other platforms in view.
  if (seeing_ == nullptr) return true;
  const std::string& known = base_views_[platform.index()];
  return seeing_->view_key(s, platform) == (known.empty() ? seeing_->view_key(base_, platform) : known);
}

Referral ReferenceMemo::refer(const episode::WorldState& s, graph::ObjectId object, graph::PlatformId platform,
                              graph::ObjectId held_item) const {
  MTG_DEMAND(!held_item.valid() || !s.held.valid(), "refer: an item is already in hand");
  const auto make = [&](const episode::WorldState& in) { return refer_in(g_, in, object, platform, held_item, rule_, seeing_); };
  if (!as_in_base(s, platform)) return make(s);
  std::string key;
  append_key(key, object.value());
  append_key(key, platform.value());
  append_key(key, held_item.value());  // -1: none
  return kept_.get(key, [&] { return make(base_); });
}

}  // namespace mtg::tasks
