#include "core/tasks/identify.h"

#include "core/util/error.h"

namespace mtg::tasks {

Identification make_identification(const graph::SceneGraph& g, int part, const std::string& role,
                                   graph::ObjectId object, graph::PlatformId platform, const Reference& r) {
  Identification id;
  id.part = part;
  id.role = role;
  id.object = g.objects[object].name;
  id.platform = g.platforms[platform].name;
  id.reference = r;
  id.phrase = r.phrase();
  return id;
}

Naming identify(const graph::SceneGraph& g, const episode::WorldState& start, const episode::AtomicGoal& goal,
                Ambiguity rule, int part, const ReferenceMemo* memo, const render::VisibilityOracle* seeing) {
  MTG_DEMAND(memo == nullptr || (memo->rule() == rule && memo->seeing() == seeing),
             "identify: the reference memo uses another ambiguity rule or view");
  // The destination looks the same with the item in hand unless the item comes from there, or
  // stands in the destination's view.
  const bool item_there = goal.source == goal.platform ||
                          (seeing != nullptr && seeing->in_view(start, goal.platform, goal.item));
  auto referred = [&](graph::ObjectId object, graph::PlatformId platform, bool while_placing) -> Referral {
    const graph::ObjectId held = while_placing && item_there ? goal.item : graph::ObjectId();
    return memo != nullptr ? memo->refer(start, object, platform, held)
                           : refer_in(g, start, object, platform, held, rule, seeing);
  };
  Naming naming;
  Identified& out = naming.identified.emplace();
  const auto item = referred(goal.item, goal.source, false);
  if (!item) return {std::nullopt, item.occluded};
  // The item is picked by its number: that number must be readable where the robot arrives.
  if (seeing != nullptr && !seeing->mark_readable(start, goal.source, goal.item)) {
    return {std::nullopt, true};
  }
  out.wording.item = *item;
  if (item->relation != Relation::kAlone) {
    out.lookalikes.push_back(make_identification(g, part, "item", goal.item, goal.source, *item));
  }
  const std::pair<graph::ObjectId, Reference*> anchors[] = {{goal.anchor, &out.wording.anchor},
                                                            {goal.anchor2, &out.wording.anchor2}};
  for (const auto& [anchor, slot] : anchors) {
    if (!anchor.valid()) continue;
    const auto r = referred(anchor, goal.platform, true);
    if (!r) return {std::nullopt, r.occluded};
    *slot = *r;
    if (r->relation != Relation::kAlone) {
      out.lookalikes.push_back(
          make_identification(g, part, anchor == goal.anchor ? "anchor" : "anchor2", anchor, goal.platform, *r));
    }
  }
  return naming;
}

bool has_lookalikes(const graph::SceneGraph& g, const episode::WorldState& start, const episode::AtomicGoal& goal,
                    Ambiguity rule) {
  if (has_lookalike(g, start, goal.item, goal.source, rule)) return true;
  if (!goal.anchor.valid()) return false;
  for (const graph::ObjectId a : goal.anchors()) {
    if (has_lookalike(g, start, a, goal.platform, rule)) return true;  // the item only removes one
  }
  return false;
}

}  // namespace mtg::tasks
