#pragma once
// 95 % intervals for the rates a run reports (docs/statistics.md). Success rates are binomial
// proportions: Wilson's score interval, which keeps its coverage at 0 and 100 % and at small n,
// where the textbook p ± 1.96·se collapses to a point. Intermediate points are bounded means of
// skewed, lumpy values (0, 25, ..., 100 and Level 3 averages): a percentile bootstrap, seeded so
// the same results always print the same interval.

#include <cstdint>
#include <vector>

namespace mtg::stats {

/// Two-sided 95 % normal quantile, z_{0.975}.
inline constexpr double kZ95 = 1.959963984540054;
/// Resamples per bootstrap interval: enough for a stable 2.5 % tail (50 draws beyond each end).
inline constexpr int kBootstrapResamples = 2000;

/// A closed interval [low, high] in the units of what it bounds.
struct Interval {
  double low = 0.0;
  double high = 0.0;
  bool operator==(const Interval&) const = default;
};

/// The arithmetic mean; 0 for no values.
double mean(const std::vector<double>& values);

/// Wilson score interval of `successes` in `trials`, as fractions in [0, 1]; [0, 0] when there
/// are no trials. Requires 0 <= successes <= trials.
Interval wilson_interval(std::int64_t successes, std::int64_t trials);

/// Wilson's interval for a proportion estimated with the precision of `effective_trials`
/// independent trials (which need not be a whole number). Requires 0 <= proportion <= 1.
Interval wilson_interval_of(double proportion, double effective_trials);

/// Successes of one stratum (a level) of an average over strata.
struct Tally {
  std::int64_t successes = 0;
  std::int64_t trials = 0;
};

/// The interval of the mean of stratum success rates (the paper's "Avg" of SR over levels):
/// Wilson's interval at that mean with the effective number of trials of an equally weighted
/// mean, L² / Σ 1/n_l (the pooled n when strata are equal). Unlike a bootstrap it does not
/// collapse to a point when every episode succeeded. Strata without trials are skipped.
Interval stratified_wilson_interval(const std::vector<Tally>& strata);

/// Percentile bootstrap interval of the mean of `values` (resampled with replacement
/// `resamples` times from a generator seeded with `seed`); a single value or none gives
/// [mean, mean].
Interval bootstrap_mean_interval(const std::vector<double>& values, std::uint64_t seed,
                                 int resamples = kBootstrapResamples);

/// The interval of a mean of stratum means (the paper's "Avg" over levels): each stratum is
/// resampled on its own, so each keeps its size, and the resampled stratum means are averaged.
/// Empty strata are skipped.
Interval bootstrap_mean_of_means_interval(const std::vector<std::vector<double>>& strata, std::uint64_t seed,
                                          int resamples = kBootstrapResamples);

/// The q-quantile (0 <= q <= 1) of sorted values by linear interpolation between order
/// statistics (Hyndman and Fan's type 7, the default of R and NumPy). Requires a non-empty input.
double quantile_of_sorted(const std::vector<double>& sorted, double q);

}  // namespace mtg::stats
