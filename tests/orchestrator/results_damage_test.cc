// Values no judge writes in results.sqlite (issue 55): refused in one line naming the row, never
// turned into "[-nan, -nan]", an 80-digit figure or a row of Level 99.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "core/store/sqlite.h"
#include "core/util/error.h"
#include "orchestrator/run/results_db.h"
#include "tests/support/result_rows.h"

namespace mtg::orchestrator {
namespace {

namespace fs = std::filesystem;

TEST(ResultsDamage, NaNInfinitiesLevelsOutOfRangeAndTextAreRefusedNamingTheRow) {
  const fs::path dir = fs::temp_directory_path() / ("mtg_results_damage_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path file = dir / "results.sqlite";
  {
    ResultsDb db(file);
    for (std::uint32_t e = 0; e < 3; ++e) db.insert(testing::scored_row(e, "s/L1/" + std::to_string(e), "oracle", 1, true));
  }
  ASSERT_EQ(read_results(file).size(), 3u);
  const std::pair<const char*, const char*> damages[] = {
      {"UPDATE episodes SET ip = 1e999 WHERE episode_id = 1", "ip inf is not between 0 and 100"},
      {"UPDATE episodes SET ip = -1e999 WHERE episode_id = 1", "is not between 0 and 100"},
      {"UPDATE episodes SET ip = 1e308 WHERE episode_id = 1", "is not between 0 and 100"},
      {"UPDATE episodes SET ip = 'NaN' WHERE episode_id = 1", "ip is not a number"},
      {"UPDATE episodes SET level = 99 WHERE episode_id = 1", "level 99 is not 1 to 4"},
      {"UPDATE episodes SET level = -7 WHERE episode_id = 1", "level -7 is not 1 to 4"},
      {"UPDATE episodes SET steps = 'many' WHERE episode_id = 1", "steps is not a number"},
  };
  for (const auto& [sql, words] : damages) {
    SCOPED_TRACE(sql);
    {
      store::Database db(file, store::Database::Mode::kReadWrite);
      db.exec("UPDATE episodes SET ip = 100, level = 1, steps = 3 WHERE episode_id = 1");
      db.exec(sql);
    }
    try {
      (void)read_results(file);
      ADD_FAILURE() << "the damage was read as figures";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file.string() + ": episode 1: "), std::string::npos) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mtg::orchestrator
