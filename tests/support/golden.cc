#include "tests/support/golden.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace mtg::testing {
namespace fs = std::filesystem;

std::string compare_golden(const std::string& name, const std::string& actual) {
  const fs::path golden = fs::path(MTG_SOURCE_DIR) / "tests" / "golden" / name;
  if (const char* update = std::getenv("MTG_UPDATE_GOLDEN"); update != nullptr && *update == '1') {
    fs::create_directories(golden.parent_path());
    std::ofstream(golden, std::ios::binary) << actual;
    return "";
  }
  std::ifstream in(golden, std::ios::binary);
  std::stringstream expected;
  expected << in.rdbuf();
  if (in && expected.str() == actual) return "";
  const fs::path out = fs::temp_directory_path() / ("actual_" + name);
  std::ofstream(out, std::ios::binary) << actual;
  return "differs from golden " + golden.string() + "; actual written to " + out.string() +
         " (diff them; MTG_UPDATE_GOLDEN=1 rewrites the golden after an intended change)";
}

}  // namespace mtg::testing
