#include "core/episode/remix.h"

#include <algorithm>

#include "core/episode/placement.h"
#include "core/util/rng.h"

namespace mtg::episode {

std::map<std::string, Eigen::Vector3d> remix_items(const graph::SceneGraph& g, std::uint64_t seed) {
  WorldState s = initial_state(g);
  Rng rng(derive_seed(seed, 0x72656d6978ull));  // "remix"
  // The items standing directly on a navigable platform (what rests on them moves along).
  std::vector<graph::ObjectId> items;
  for (const graph::PlatformId p : g.navigable) {
    for (const graph::ObjectId o : objects_on(s, p)) {
      if (g.objects[o].pickable()) items.push_back(o);
    }
  }
  rng.shuffle(items);
  for (const graph::ObjectId o : items) {
    const graph::PlatformId from = s.objects[o].parent;
    const Eigen::Vector2d back = s.objects[o].position.head<2>();
    pick(g, s, o);
    std::vector<graph::PlatformId> destinations = g.navigable;
    rng.shuffle(destinations);
    bool placed = false;
    for (const graph::PlatformId p : destinations) {
      if (stack_height(g, s, o) > g.platforms[p].clearance) continue;
      const int side = std::max(0, g.platforms[p].default_side);
      WorldState placing = s;
      placing.at_platform = p;
      placing.side = side;
      placing.phase = Phase::kPlacing;
      const FeasibleCentres feasible = held_feasible_centres(g, placing, p);
      if (feasible.empty()) continue;
      std::vector<PlaceTarget> targets = place_targets(g, placing, p, static_cast<graph::Side>(side), 0.03);
      rng.shuffle(targets);
      for (const PlaceTarget& t : targets) {
        if (t.kind == PlaceTarget::Kind::kAnywhere) continue;
        if (const auto xy = resolve_target(g, placing, p, t, feasible)) {
          place_held(g, s, p, *xy);
          placed = true;
          break;
        }
      }
      if (placed) break;
    }
    // Nowhere else it fits: it goes back where it stood.
    if (!placed) place_held(g, s, from, back);
  }
  std::map<std::string, Eigen::Vector3d> moved;
  for (const graph::ObjectId o : g.objects.ids()) {
    const Eigen::Vector3d d = s.objects[o].position - g.objects[o].X_WO.translation();
    if (d.norm() > 1e-9) moved[g.objects[o].name] = d;
  }
  return moved;
}

}  // namespace mtg::episode
