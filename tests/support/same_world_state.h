#pragma once
// Whether two world states are the same bit for bit (every field of WorldState and ObjectState):
// a state rebuilt from its delta, through the bus or not, must be.

#include <gtest/gtest.h>

#include "core/episode/world_state.h"

namespace mtg::testing {

inline void expect_same_world_state(const episode::WorldState& a, const episode::WorldState& b) {
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (const graph::ObjectId i : a.objects.ids()) {
    EXPECT_EQ(a.objects[i].parent, b.objects[i].parent) << i;
    EXPECT_EQ(a.objects[i].position, b.objects[i].position) << i;
    EXPECT_EQ(a.objects[i].footprint, b.objects[i].footprint) << i;
    EXPECT_EQ(a.objects[i].bottom, b.objects[i].bottom) << i;
    EXPECT_EQ(a.objects[i].top, b.objects[i].top) << i;
    EXPECT_EQ(a.objects[i].placed_side, b.objects[i].placed_side) << i;
  }
  EXPECT_EQ(a.children, b.children);
  EXPECT_EQ(a.platform_offset, b.platform_offset);
  EXPECT_EQ(a.held, b.held);
  EXPECT_EQ(a.at_platform, b.at_platform);
  EXPECT_EQ(a.side, b.side);
  EXPECT_EQ(a.phase, b.phase);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.numbering, b.numbering);
  // The numbers kept: a platform without any is numbered as pickable_on says in both.
  ASSERT_EQ(a.numbered.size(), b.numbered.size());
  for (const graph::PlatformId p : a.numbered.ids()) EXPECT_EQ(a.numbered[p], b.numbered[p]) << p;
}

}  // namespace mtg::testing
