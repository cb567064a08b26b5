#pragma once
// Access to the shipped ReplicaCAD copy for tests on real data. When no dataset is found the
// tests skip with a message naming where they looked (set $MTG_DATA_DIR to point at one).

#include <gtest/gtest.h>

#include <optional>

#include "core/scene/dataset.h"

namespace mtg::testing {

/// The indexed dataset, or nullopt (with `why` filled) when none is found.
const std::optional<scene::Dataset>& shipped_dataset(std::string* why = nullptr);

}  // namespace mtg::testing

#define MTG_REQUIRE_SHIPPED_DATA()                                          \
  do {                                                                      \
    std::string why_;                                                       \
    if (!::mtg::testing::shipped_dataset(&why_)) GTEST_SKIP() << why_;      \
  } while (false)
