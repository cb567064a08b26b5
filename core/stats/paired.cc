#include "core/stats/paired.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/util/error.h"
#include "core/util/rng.h"

namespace mtg::stats {
namespace {

double log_choose(std::int64_t n, std::int64_t k) {
  return std::lgamma(static_cast<double>(n) + 1.0) - std::lgamma(static_cast<double>(k) + 1.0) -
         std::lgamma(static_cast<double>(n - k) + 1.0);
}

// Differences within this of the observed one count as "as extreme": sums of the same terms in
// another order differ in the last bits.
constexpr double kTie = 1e-9;

double sign_flip_p(const std::vector<double>& d, std::uint64_t seed, int resamples) {
  const double observed = std::abs(std::accumulate(d.begin(), d.end(), 0.0));
  if (d.size() <= static_cast<std::size_t>(kExactSignFlips)) {
    const std::uint64_t signs = std::uint64_t{1} << d.size();
    std::uint64_t hits = 0;
    for (std::uint64_t mask = 0; mask < signs; ++mask) {
      double sum = 0.0;
      for (std::size_t i = 0; i < d.size(); ++i) sum += (mask >> i & 1u) ? -d[i] : d[i];
      if (std::abs(sum) >= observed - kTie) ++hits;
    }
    return static_cast<double>(hits) / static_cast<double>(signs);
  }
  Rng rng(seed);
  std::int64_t hits = 0;
  for (int r = 0; r < resamples; ++r) {
    double sum = 0.0;
    std::uint64_t bits = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      if (i % 64 == 0) bits = rng.next_u64();
      sum += (bits >> (i % 64) & 1u) ? -d[i] : d[i];
    }
    if (std::abs(sum) >= observed - kTie) ++hits;
  }
  return static_cast<double>(1 + hits) / static_cast<double>(1 + resamples);
}

}  // namespace

double mcnemar_exact_p(std::int64_t only_a, std::int64_t only_b) {
  MTG_DEMAND(only_a >= 0 && only_b >= 0, "mcnemar_exact_p needs counts >= 0");
  const std::int64_t n = only_a + only_b;
  if (n == 0) return 1.0;
  const std::int64_t k = std::min(only_a, only_b);
  double tail = 0.0;
  for (std::int64_t i = 0; i <= k; ++i) tail += std::exp(log_choose(n, i) - static_cast<double>(n) * std::log(2.0));
  return std::min(1.0, 2.0 * tail);
}

PairedDifference paired_difference(const std::vector<double>& a, const std::vector<double>& b, std::uint64_t seed,
                                   int resamples) {
  MTG_DEMAND(a.size() == b.size(), "paired_difference needs as many values on each side");
  PairedDifference out;
  out.pairs = static_cast<std::int64_t>(a.size());
  if (a.empty()) {
    out.detectable = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  std::vector<double> d(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) d[i] = b[i] - a[i];
  out.mean = mean(d);
  out.interval = bootstrap_mean_interval(d, derive_seed(seed, 1), resamples);
  out.p = sign_flip_p(d, derive_seed(seed, 2), resamples);
  if (d.size() < 2) {
    out.detectable = std::numeric_limits<double>::quiet_NaN();
  } else {
    double ss = 0.0;
    for (const double x : d) ss += (x - out.mean) * (x - out.mean);
    const double sd = std::sqrt(ss / static_cast<double>(d.size() - 1));
    out.detectable = kZ95Power80 * sd / std::sqrt(static_cast<double>(d.size()));
  }
  return out;
}

std::vector<double> holm_adjusted(const std::vector<double>& p) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return p[x] < p[y]; });
  std::vector<double> adjusted(p.size());
  double running = 0.0;
  for (std::size_t rank = 0; rank < order.size(); ++rank) {
    running = std::max(running, std::min(1.0, static_cast<double>(p.size() - rank) * p[order[rank]]));
    adjusted[order[rank]] = running;
  }
  return adjusted;
}

}  // namespace mtg::stats
