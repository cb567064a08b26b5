#pragma once
// Paired comparisons of two agents (or two runs) on the same tasks (docs/statistics.md). Pairing
// removes what the tasks themselves contribute, so a difference needs far fewer episodes to show
// than two independent rates would.

#include <cstdint>
#include <vector>

#include "core/stats/intervals.h"

namespace mtg::stats {

/// Exact McNemar test on success: of the discordant pairs, `only_a` succeeded for A alone and
/// `only_b` for B alone. Under "no difference" each discordant pair is a fair coin, so the
/// two-sided p is min(1, 2·P[X <= min(only_a, only_b)]) for X ~ Binomial(only_a + only_b, 1/2);
/// 1 when there are no discordant pairs.
double mcnemar_exact_p(std::int64_t only_a, std::int64_t only_b);

/// The mean paired difference b[i] - a[i] with what can be said about it.
struct PairedDifference {
  std::int64_t pairs = 0;
  double mean = 0.0;
  Interval interval;  ///< percentile bootstrap over pairs, 95 %
  /// Two-sided sign-flip permutation p of the mean difference (each pair's difference is equally
  /// likely to have either sign when A and B do not differ): exact over all 2^n signs when
  /// n <= kExactSignFlips, else Monte Carlo with `resamples` draws, p = (1 + hits) / (1 + draws).
  double p = 1.0;
  /// The smallest true mean difference a two-sided 5 % test would find with 80 % power, given
  /// the spread of the differences seen: (z_0.975 + z_0.8)·s_d/√n. NaN below two pairs.
  double detectable = 0.0;
};

inline constexpr int kExactSignFlips = 16;
/// z_{0.975} + z_{0.80}: a two-sided 5 % test with 80 % power.
inline constexpr double kZ95Power80 = 1.959963984540054 + 0.8416212335729143;

/// Requires a.size() == b.size().
PairedDifference paired_difference(const std::vector<double>& a, const std::vector<double>& b, std::uint64_t seed,
                                   int resamples = kBootstrapResamples);

/// Holm's step-down adjustment of several p-values (one family of tests): the i-th smallest is
/// multiplied by (m - i), running maxima keep the order, and nothing exceeds 1. Returned in the
/// order given.
std::vector<double> holm_adjusted(const std::vector<double>& p);

}  // namespace mtg::stats
