// MemoTable: a value is made once per key and handed back as stored, from any thread.

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "core/util/memo_table.h"

namespace mtg {
namespace {

TEST(MemoTable, MakesAValueOncePerKeyAndHandsBackTheStoredOne) {
  MemoTable<std::string> table;
  int made = 0;
  const auto make = [&] { return "value " + std::to_string(++made); };
  std::string key;
  append_key(key, 1.5);
  const std::string& first = table.get(key, make);
  const std::string& again = table.get(key, make);
  EXPECT_EQ(first, "value 1");
  EXPECT_EQ(&first, &again) << "a hit is the stored value itself";
  std::string other;
  append_key(other, -1.5);
  EXPECT_EQ(table.get(other, make), "value 2");
  EXPECT_EQ(made, 2);
  EXPECT_EQ(table.size(), 2u);
  EXPECT_EQ(&table.get(key, make), &first) << "values stay where they are as the table grows";
}

TEST(MemoTable, ThreadsAskingForTheSameKeysAllGetTheOneStoredValue) {
  MemoTable<std::vector<int>> table;
  std::atomic<int> made = 0;
  std::vector<std::thread> threads;
  std::vector<const std::vector<int>*> seen(4 * 100);
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int k = 0; k < 100; ++k) {
        std::string key;
        append_key(key, k);
        seen[static_cast<std::size_t>(100 * t + k)] = &table.get(key, [&] {
          ++made;
          return std::vector<int>(16, k);
        });
      }
    });
  }
  for (std::thread& th : threads) th.join();
  EXPECT_EQ(table.size(), 100u);
  EXPECT_GE(made.load(), 100);
  for (int t = 1; t < 4; ++t) {
    for (int k = 0; k < 100; ++k) {
      EXPECT_EQ(seen[static_cast<std::size_t>(100 * t + k)], seen[static_cast<std::size_t>(k)]);
      EXPECT_EQ(*seen[static_cast<std::size_t>(k)], std::vector<int>(16, k));
    }
  }
}

// Full, a bounded table forgets what it holds and starts again: a forgotten key is made anew (the
// same value: it is a memo), the others are handed back, and it never holds more than asked.
TEST(BoundedMemoTable, ForgetsWhenFullAndMakesAForgottenValueAgain) {
  BoundedMemoTable<std::string> table(2);
  int made = 0;
  const auto value_of = [&](int k) {
    std::string key;
    append_key(key, k);
    return table.get(key, [&] {
      ++made;
      return "value " + std::to_string(k);
    });
  };
  EXPECT_EQ(value_of(1), "value 1");
  EXPECT_EQ(value_of(2), "value 2");
  EXPECT_EQ(value_of(1), "value 1");
  EXPECT_EQ(made, 2) << "a hit makes nothing";
  EXPECT_EQ(value_of(3), "value 3");
  EXPECT_LE(table.size(), 2u);
  EXPECT_EQ(value_of(1), "value 1");
  EXPECT_EQ(value_of(2), "value 2");
  EXPECT_EQ(made, 5) << "1 and 2 were forgotten when 3 came, and made again";
  EXPECT_LE(table.size(), 2u);
}

}  // namespace
}  // namespace mtg
