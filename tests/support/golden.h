#pragma once
// Golden-file comparison: the expected text lives in tests/golden/; on a mismatch the actual
// text is written beside the build's test output so `diff` shows what changed. Set
// MTG_UPDATE_GOLDEN=1 to rewrite the golden files after an intended change.

#include <string>

namespace mtg::testing {

/// Returns "" when `actual` equals tests/golden/<name>, else a message naming both files.
std::string compare_golden(const std::string& name, const std::string& actual);

}  // namespace mtg::testing
