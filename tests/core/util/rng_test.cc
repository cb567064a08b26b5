#include "core/util/rng.h"

#include <gtest/gtest.h>

#include <set>

namespace mtg {
namespace {

TEST(Rng, SameSeedSameSequence) {
  Rng a(42), b(42);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.next_u64(), b.next_u64());
}

TEST(Rng, ValuesArePinnedAcrossPlatforms) {
  // Task sets and runs are reproducible byte for byte only if these never change.
  Rng r(7);
  EXPECT_EQ(r.next_u64(), 12923355070828475994ull);  // xoshiro256** reference value
  EXPECT_EQ(r.uniform_index(1000), 278u);
  EXPECT_EQ(derive_seed(1, 2), 8653772725559322046ull);
}

TEST(Rng, UniformIndexStaysInRangeAndCoversIt) {
  Rng r(1);
  std::set<std::uint64_t> seen;
  for (int i = 0; i < 1000; ++i) {
    const auto v = r.uniform_index(7);
    ASSERT_LT(v, 7u);
    seen.insert(v);
  }
  EXPECT_EQ(seen.size(), 7u);
}

TEST(Rng, ShuffleIsAPermutation) {
  Rng r(3);
  std::vector<int> v = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  r.shuffle(v);
  std::multiset<int> s(v.begin(), v.end());
  EXPECT_EQ(s, (std::multiset<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_NE(v, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
}

TEST(Rng, DerivedSeedsDiffer) {
  EXPECT_NE(derive_seed(1, 2), derive_seed(2, 1));
  EXPECT_NE(derive_seed(1, 2), derive_seed(1, 3));
}

}  // namespace
}  // namespace mtg
