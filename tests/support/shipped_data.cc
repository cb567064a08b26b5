#include "tests/support/shipped_data.h"

#include "core/util/error.h"

namespace mtg::testing {

const std::optional<scene::Dataset>& shipped_dataset(std::string* why) {
  static std::string reason;
  static const std::optional<scene::Dataset> dataset = []() -> std::optional<scene::Dataset> {
    try {
      return scene::index_dataset(scene::resolve_data_root());
    } catch (const Error& e) {
      reason = std::string("shipped dataset not available: ") + e.what();
      return std::nullopt;
    }
  }();
  if (why != nullptr) *why = reason;
  return dataset;
}

}  // namespace mtg::testing
