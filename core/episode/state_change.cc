#include "core/episode/state_change.h"

#include <cstring>

#include "core/util/error.h"

namespace mtg::episode {
namespace {

// Bitwise: a value equal under == may still differ in its bits (a zero's sign).
template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

bool same_bits(const geom::Ring& a, const geom::Ring& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

bool same_bits(const ObjectState& a, const ObjectState& b) {
  return a.parent == b.parent && same_bits(a.position, b.position) && same_bits(a.footprint, b.footprint) &&
         same_bits(a.bottom, b.bottom) && same_bits(a.top, b.top) && a.placed_side == b.placed_side;
}

// The entries of a per-platform table that differ between two states.
template <class T, class Same>
void changed_entries(const IdVector<graph::PlatformId, T>& from, const IdVector<graph::PlatformId, T>& to, Same same,
                     std::vector<std::pair<graph::PlatformId, T>>& out) {
  for (const graph::PlatformId p : to.ids()) {
    if (!same(from[p], to[p])) out.emplace_back(p, to[p]);
  }
}

}  // namespace

StateChange change_between(const WorldState& from, const WorldState& to) {
  // The numbering table is sized on first use (world_state.cc), so `to` may hold more of it.
  MTG_DEMAND(from.objects.size() == to.objects.size() && from.children.size() == to.children.size() &&
                 from.platform_offset.size() == to.platform_offset.size() &&
                 from.numbered.size() <= to.numbered.size(),
             "state change: the two states are of different scene graphs");
  StateChange c;
  for (const graph::ObjectId o : to.objects.ids()) {
    if (!same_bits(from.objects[o], to.objects[o])) c.objects.emplace_back(o, to.objects[o]);
  }
  const auto same_list = [](const std::vector<graph::ObjectId>& a, const std::vector<graph::ObjectId>& b) { return a == b; };
  changed_entries(from.children, to.children, same_list, c.children);
  changed_entries(from.platform_offset, to.platform_offset,
                  [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return same_bits(a, b); }, c.offsets);
  c.numbered_size = to.numbered.size();
  for (const graph::PlatformId p : to.numbered.ids()) {
    const bool had = p.index() < from.numbered.size();
    if (had ? from.numbered[p] != to.numbered[p] : !to.numbered[p].empty()) c.numbered.emplace_back(p, to.numbered[p]);
  }
  c.held = to.held;
  c.at_platform = to.at_platform;
  c.side = to.side;
  c.phase = to.phase;
  c.steps = to.steps;
  c.numbering = to.numbering;
  return c;
}

void apply_change(WorldState& s, const StateChange& change) {
  for (const auto& [o, state] : change.objects) s.objects.at(o) = state;
  for (const auto& [p, list] : change.children) s.children.at(p) = list;
  for (const auto& [p, offset] : change.offsets) s.platform_offset.at(p) = offset;
  if (s.numbered.size() < change.numbered_size) s.numbered.resize(change.numbered_size);
  for (const auto& [p, list] : change.numbered) s.numbered.at(p) = list;
  s.held = change.held;
  s.at_platform = change.at_platform;
  s.side = change.side;
  s.phase = change.phase;
  s.steps = change.steps;
  s.numbering = change.numbering;
}

}  // namespace mtg::episode
