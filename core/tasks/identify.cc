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

std::optional<Identified> identify(const graph::SceneGraph& g, const episode::WorldState& start,
                                   const episode::AtomicGoal& goal, Ambiguity rule, int part,
                                   const ReferenceMemo* memo) {
  MTG_DEMAND(memo == nullptr || memo->rule() == rule, "identify: the reference memo uses another ambiguity rule");
  // The destination looks the same with the item in hand unless the item comes from there.
  const bool same_platform = goal.source == goal.platform;
  auto referred = [&](graph::ObjectId object, graph::PlatformId platform,
                      bool while_placing) -> std::optional<Reference> {
    const graph::ObjectId held = while_placing && same_platform ? goal.item : graph::ObjectId();
    return memo != nullptr ? memo->refer(start, object, platform, held) : refer_in(g, start, object, platform, held, rule);
  };
  Identified out;
  const auto item = referred(goal.item, goal.source, false);
  if (!item) return std::nullopt;
  out.wording.item = *item;
  if (item->relation != Relation::kAlone) {
    out.lookalikes.push_back(make_identification(g, part, "item", goal.item, goal.source, *item));
  }
  const std::pair<graph::ObjectId, Reference*> anchors[] = {{goal.anchor, &out.wording.anchor},
                                                            {goal.anchor2, &out.wording.anchor2}};
  for (const auto& [anchor, slot] : anchors) {
    if (!anchor.valid()) continue;
    const auto r = referred(anchor, goal.platform, true);
    if (!r) return std::nullopt;
    *slot = *r;
    if (r->relation != Relation::kAlone) {
      out.lookalikes.push_back(
          make_identification(g, part, anchor == goal.anchor ? "anchor" : "anchor2", anchor, goal.platform, *r));
    }
  }
  return out;
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
