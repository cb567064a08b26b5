#include "core/stats/intervals.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/util/error.h"
#include "core/util/rng.h"

namespace mtg::stats {
namespace {

double resampled_mean(const std::vector<double>& values, Rng& rng) {
  double sum = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) sum += values[rng.uniform_index(values.size())];
  return sum / static_cast<double>(values.size());
}

Interval percentile_interval(std::vector<double> estimates) {
  std::sort(estimates.begin(), estimates.end());
  return {quantile_of_sorted(estimates, 0.025), quantile_of_sorted(estimates, 0.975)};
}

}  // namespace

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

Interval wilson_interval_of(double p, double n) {
  MTG_DEMAND(p >= 0.0 && p <= 1.0, "wilson_interval_of needs a proportion in [0, 1]");
  if (n <= 0.0) return {};
  const double z2 = kZ95 * kZ95;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half = kZ95 * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n)) / (1.0 + z2 / n);
  // At p = 0 or 1 one end is exactly 0 or 1; rounding must not leave it at 1e-17.
  return {p == 0.0 ? 0.0 : std::max(0.0, centre - half), p == 1.0 ? 1.0 : std::min(1.0, centre + half)};
}

Interval wilson_interval(std::int64_t successes, std::int64_t trials) {
  MTG_DEMAND(successes >= 0 && successes <= trials, "wilson_interval needs 0 <= successes <= trials");
  if (trials == 0) return {};
  return wilson_interval_of(static_cast<double>(successes) / static_cast<double>(trials), static_cast<double>(trials));
}

Interval stratified_wilson_interval(const std::vector<Tally>& strata) {
  double mean = 0.0, inverse_sizes = 0.0, kept = 0.0;
  for (const Tally& t : strata) {
    MTG_DEMAND(t.successes >= 0 && t.successes <= t.trials, "stratified_wilson_interval needs 0 <= successes <= trials");
    if (t.trials == 0) continue;
    mean += static_cast<double>(t.successes) / static_cast<double>(t.trials);
    inverse_sizes += 1.0 / static_cast<double>(t.trials);
    kept += 1.0;
  }
  if (kept == 0.0) return {};
  return wilson_interval_of(std::clamp(mean / kept, 0.0, 1.0), kept * kept / inverse_sizes);
}

double quantile_of_sorted(const std::vector<double>& sorted, double q) {
  MTG_DEMAND(!sorted.empty() && q >= 0.0 && q <= 1.0, "quantile_of_sorted needs values and 0 <= q <= 1");
  const double h = q * static_cast<double>(sorted.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (h - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

Interval bootstrap_mean_interval(const std::vector<double>& values, std::uint64_t seed, int resamples) {
  MTG_DEMAND(resamples > 0, "bootstrap needs at least one resample");
  if (values.size() < 2) return {mean(values), mean(values)};
  Rng rng(seed);
  std::vector<double> means(static_cast<std::size_t>(resamples));
  for (double& m : means) m = resampled_mean(values, rng);
  return percentile_interval(std::move(means));
}

Interval bootstrap_mean_of_means_interval(const std::vector<std::vector<double>>& strata, std::uint64_t seed,
                                          int resamples) {
  MTG_DEMAND(resamples > 0, "bootstrap needs at least one resample");
  std::vector<const std::vector<double>*> kept;
  for (const auto& s : strata) {
    if (!s.empty()) kept.push_back(&s);
  }
  if (kept.empty()) return {};
  Rng rng(seed);
  std::vector<double> means(static_cast<std::size_t>(resamples));
  for (double& m : means) {
    double sum = 0.0;
    for (const auto* s : kept) sum += s->size() < 2 ? mean(*s) : resampled_mean(*s, rng);
    m = sum / static_cast<double>(kept.size());
  }
  return percentile_interval(std::move(means));
}

}  // namespace mtg::stats
