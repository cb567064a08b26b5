// The renderer pool's plan (core/render/render_pool.h): sizes, GPUs and shares of the cores.

#include <gtest/gtest.h>

#include "core/render/render_pool.h"
#include "core/util/error.h"

namespace mtg::render {
namespace {

TEST(RenderPool, DefaultSizeIsARendererPerFourCoresAtLeastOnePerGpuAtMostEight) {
  EXPECT_EQ(default_renderers(1, 0), 1);
  EXPECT_EQ(default_renderers(2, 0), 1);
  EXPECT_EQ(default_renderers(16, 0), 4);
  EXPECT_EQ(default_renderers(16, 1), 4);
  EXPECT_EQ(default_renderers(8, 4), 4);
  EXPECT_EQ(default_renderers(64, 8), 8);
  EXPECT_EQ(default_renderers(128, 0), 8) << "each holds the scenes: at most eight unless asked";
  EXPECT_EQ(default_renderers(128, 12), 12) << "but one per GPU";
  EXPECT_EQ(plan_render_pool(12, 128, 0).size(), 12u);
}

TEST(RenderPool, WithoutAGpuEachRendererDrawsAndEncodesOnItsShareOfTheCores) {
  // Two cores, two renderers: llvmpipe and the encoders get one core each, so two renderers
  // never run more threads than one renderer on both cores (the bench compares them so).
  const auto two = plan_render_pool(2, 2, 0);
  ASSERT_EQ(two.size(), 2u);
  for (const RendererSlot& s : two) {
    EXPECT_EQ(s.gpu, -1);
    EXPECT_EQ(s.draw_threads, 1);
    EXPECT_EQ(s.encode_threads, 1);
  }
  EXPECT_EQ(two[1].index, 1);
  const auto one = plan_render_pool(1, 2, 0);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].draw_threads, 2);
  // Uneven shares: the first ones get the remainder.
  const auto three = plan_render_pool(3, 8, 0);
  EXPECT_EQ(three[0].encode_threads, 3);
  EXPECT_EQ(three[1].encode_threads, 3);
  EXPECT_EQ(three[2].encode_threads, 2);
  // More renderers than cores: one thread each, not none.
  for (const RendererSlot& s : plan_render_pool(4, 2, 0)) EXPECT_EQ(s.encode_threads, 1);
}

TEST(RenderPool, RenderersGoRoundTheGpusAndLeaveLlvmpipeAlone) {
  const auto pool = plan_render_pool(0, 16, 2);
  ASSERT_EQ(pool.size(), 4u);
  EXPECT_EQ(pool[0].gpu, 0);
  EXPECT_EQ(pool[1].gpu, 1);
  EXPECT_EQ(pool[2].gpu, 0);
  EXPECT_EQ(pool[3].gpu, 1);
  for (const RendererSlot& s : pool) {
    EXPECT_EQ(s.draw_threads, 0);
    EXPECT_EQ(s.encode_threads, 4);
  }
  EXPECT_THROW(plan_render_pool(-1, 2, 0), Error);
}

TEST(RenderPool, ANewEpisodeGoesToTheRendererHoldingFewestTheFirstOnATie) {
  EXPECT_EQ(least_loaded({}), 0);
  EXPECT_EQ(least_loaded({0}), 0);
  EXPECT_EQ(least_loaded({2, 1, 1}), 1);
  EXPECT_EQ(least_loaded({0, 0}), 0);
  EXPECT_EQ(least_loaded({3, 2, 0}), 2);
}

}  // namespace
}  // namespace mtg::render
