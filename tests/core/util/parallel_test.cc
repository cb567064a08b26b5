#include "core/util/parallel.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace mtg {
namespace {

TEST(ParallelFor, EveryIndexOnceIntoItsOwnSlot) {
  for (const int jobs : {1, 2, 7}) {
    std::vector<int> hits(1000, 0);
    parallel_for(hits.size(), jobs, [&](std::size_t i) { hits[i] += static_cast<int>(i); });
    for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i], static_cast<int>(i)) << "jobs " << jobs;
  }
}

// The error a caller sees must not depend on the thread count: the lowest failing index wins.
TEST(ParallelFor, TheLowestFailingIndexIsRethrownAfterEveryThreadStopped) {
  for (const int jobs : {1, 4}) {
    try {
      parallel_for(100, jobs, [](std::size_t i) {
        if (i == 3 || i == 60) throw std::runtime_error("index " + std::to_string(i));
      });
      ADD_FAILURE() << "expected a throw";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "index 3") << "jobs " << jobs;
    }
  }
}

}  // namespace
}  // namespace mtg
