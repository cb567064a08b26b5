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

// The fields a change keeps whole (a state and a change name them alike).
template <class From, class To>
void copy_robot(const From& from, To& to) {
  to.held = from.held;
  to.at_platform = from.at_platform;
  to.side = from.side;
  to.phase = from.phase;
  to.steps = from.steps;
  to.numbering = from.numbering;
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
  copy_robot(to, c);
  return c;
}

void apply_change(WorldState& s, const StateChange& change) {
  for (const auto& [o, state] : change.objects) s.objects.at(o) = state;
  for (const auto& [p, list] : change.children) s.children.at(p) = list;
  for (const auto& [p, offset] : change.offsets) s.platform_offset.at(p) = offset;
  if (s.numbered.size() < change.numbered_size) s.numbered.resize(change.numbered_size);
  for (const auto& [p, list] : change.numbered) s.numbered.at(p) = list;
  copy_robot(change, s);
}

}  // namespace mtg::episode
