#include "core/stats/repeats.h"

#include "core/util/error.h"

namespace mtg::stats {
namespace {

// C(a, k) / C(n, k) as a product of k ratios (a <= n): no factorial overflows at n in the
// hundreds, and exactly 0 when a < k.
double choose_ratio(int a, int n, int k) {
  if (a < k) return 0.0;
  double r = 1.0;
  for (int i = 0; i < k; ++i) r *= static_cast<double>(a - i) / static_cast<double>(n - i);
  return r;
}

void check(int n, int c, int k) {
  MTG_DEMAND(n >= 1 && k >= 1 && k <= n && c >= 0 && c <= n, "pass@k needs 1 <= k <= n and 0 <= c <= n");
}

}  // namespace

double pass_at_k(int n, int c, int k) {
  check(n, c, k);
  return 1.0 - choose_ratio(n - c, n, k);
}

double pass_hat_k(int n, int c, int k) {
  check(n, c, k);
  return choose_ratio(c, n, k);
}

}  // namespace mtg::stats
