#pragma once
// How many tasks a paired comparison needs before it is paid for (docs/statistics.md, "Sizing a
// suite"). Two agents on the same tasks differ only on the discordant tasks (one succeeds, the
// other fails); McNemar's test looks at those alone, so the size follows from how often the agents
// disagree (the discordance ψ) and the difference δ in success rate one wants to see.

#include <cstdint>

namespace mtg::stats {

/// Φ⁻¹(p), the standard normal quantile, for 0 < p < 1 (to about 1e-12).
double normal_quantile(double p);

struct McNemarSizeInputs {
  double difference = 0.1;   ///< δ: the SR difference to detect, as a proportion (0.1 = 10 points)
  double discordance = 0.3;  ///< ψ = P(only A succeeds) + P(only B succeeds), δ <= ψ <= 1
  double alpha = 0.05;       ///< two-sided
  double power = 0.8;        ///< 1 - β
};

struct McNemarSize {
  double z_alpha = 0.0;  ///< z_{1-α/2}
  double z_beta = 0.0;   ///< z_{1-β}
  double exact = 0.0;    ///< the formula's value before rounding up
  std::int64_t pairs = 0;  ///< tasks (paired episodes) needed
};

/// Connor's (1987) normal approximation for McNemar's test:
///   n = (z_{1-α/2}·√ψ + z_{1-β}·√(ψ − δ²))² / δ², rounded up.
/// @throws mtg::Error naming the input that is out of range (δ outside (0, 1], ψ outside [δ, 1],
/// α or power outside (0, 1)).
McNemarSize mcnemar_pairs_needed(const McNemarSizeInputs& in);

}  // namespace mtg::stats
