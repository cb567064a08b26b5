#include "core/util/agreement.h"

#include <map>

#include "core/util/error.h"

namespace mtg {

Agreement agreement(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  if (a.size() != b.size()) {
    throw Error("agreement: " + std::to_string(a.size()) + " answers against " + std::to_string(b.size()));
  }
  Agreement out;
  out.questions = static_cast<int>(a.size());
  if (a.empty()) return out;
  std::map<std::string, std::pair<int, int>> rates;  // category -> (times a said it, times b said it)
  for (std::size_t i = 0; i < a.size(); ++i) {
    out.equal += a[i] == b[i] ? 1 : 0;
    ++rates[a[i]].first;
    ++rates[b[i]].second;
  }
  const double n = static_cast<double>(a.size());
  const double observed = out.equal / n;
  double expected = 0.0;
  for (const auto& [category, counts] : rates) expected += (counts.first / n) * (counts.second / n);
  out.percent = 100.0 * observed;
  out.kappa = expected >= 1.0 ? 1.0 : (observed - expected) / (1.0 - expected);
  return out;
}

}  // namespace mtg
