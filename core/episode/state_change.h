#pragma once
// What some steps changed in a world state, kept so that the same steps can be played again on
// the state they started from without playing them: the objects, platform tables and robot
// fields that differ, bit for bit. A change is a few objects where a whole state is hundreds, so
// task generation keeps one per plan it has made (Level 4's plans from the initial state repeat
// their first move across bindings; docs/tasks.md).

#include <cstddef>
#include <utility>
#include <vector>

#include "core/episode/world_state.h"

namespace mtg::episode {

struct StateChange {
  std::vector<std::pair<graph::ObjectId, ObjectState>> objects;
  std::vector<std::pair<graph::PlatformId, std::vector<graph::ObjectId>>> children;
  std::vector<std::pair<graph::PlatformId, Eigen::Vector3d>> offsets;
  std::vector<std::pair<graph::PlatformId, std::vector<graph::ObjectId>>> numbered;
  std::size_t numbered_size = 0;  // the numbering table's size afterwards
  // The robot's fields and the step count, whole.
  graph::ObjectId held;
  graph::PlatformId at_platform;
  int side = -1;
  Phase phase = Phase::kStart;
  int steps = 0;
  Numbering numbering = Numbering::kStable;
};

/// What turns `from` into `to` (two states of one scene graph). Entries are compared by their
/// bits, so 0.0 and -0.0 differ and the change gives back `to` exactly.
StateChange change_between(const WorldState& from, const WorldState& to);

/// Makes `s` (a state equal to the `from` of the change) the `to` of the change.
void apply_change(WorldState& s, const StateChange& change);

}  // namespace mtg::episode
