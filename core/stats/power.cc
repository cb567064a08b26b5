#include "core/stats/power.h"

#include <cmath>
#include <string>

#include "core/util/error.h"

namespace mtg::stats {

namespace {

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

std::string figure(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) throw Error("normal quantile of " + figure(p) + ": p must lie strictly between 0 and 1");
  // Bisection on erfc: no table to get wrong, and exact to the bracket's width in 200 halvings.
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (normal_cdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

McNemarSize mcnemar_pairs_needed(const McNemarSizeInputs& in) {
  const double d = in.difference, psi = in.discordance;
  if (!(d > 0.0 && d <= 1.0)) throw Error("the difference to detect must be above 0 and at most 100 points, not " + figure(100 * d));
  if (!(psi >= d && psi <= 1.0)) {
    throw Error("the discordance (share of tasks where exactly one agent succeeds) must lie between the difference (" +
                figure(d) + ") and 1, not " + figure(psi));
  }
  if (!(in.alpha > 0.0 && in.alpha < 1.0)) throw Error("alpha must lie between 0 and 1, not " + figure(in.alpha));
  if (!(in.power > 0.0 && in.power < 1.0)) throw Error("power must lie between 0 and 1, not " + figure(in.power));
  McNemarSize s;
  s.z_alpha = normal_quantile(1.0 - in.alpha / 2.0);
  s.z_beta = normal_quantile(in.power);
  const double root = s.z_alpha * std::sqrt(psi) + s.z_beta * std::sqrt(psi - d * d);
  s.exact = root * root / (d * d);
  // 1e-9 keeps a value that is whole up to rounding (e.g. 196.0000000001) from becoming 197.
  s.pairs = static_cast<std::int64_t>(std::ceil(s.exact - 1e-9));
  return s;
}

}  // namespace mtg::stats
