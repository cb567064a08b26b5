#include "core/tasks/identify.h"

namespace mtg::tasks {
namespace {

// The start state with the item in hand: what the destination looks like while placing.
episode::WorldState with_item_held(const graph::SceneGraph& g, const episode::WorldState& start,
                                   graph::ObjectId item) {
  episode::WorldState held = start;
  episode::pick(g, held, item);
  return held;
}

}  // namespace

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
                                   const episode::AtomicGoal& goal, Ambiguity rule, int part, ReferenceMemo* memo) {
  // The destination looks the same with the item in hand unless the item comes from there.
  const bool same_platform = goal.source == goal.platform;
  std::optional<episode::WorldState> held;
  auto referred = [&](graph::ObjectId object, graph::PlatformId platform,
                      bool while_placing) -> std::optional<Reference> {
    const bool two_states = while_placing && same_platform;
    const auto key = std::make_tuple(object, platform, two_states ? goal.item : graph::ObjectId());
    if (memo != nullptr) {
      if (const auto it = memo->find(key); it != memo->end()) return it->second;
    }
    if (two_states && !held) held = with_item_held(g, start, goal.item);
    auto r = two_states ? refer(g, {&start, &*held}, object, platform, rule) : refer(g, {&start}, object, platform, rule);
    if (memo != nullptr) memo->emplace(key, r);
    return r;
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
