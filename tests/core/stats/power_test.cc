// Sizing a paired comparison before paying for it (core/stats/power.h).

#include <gtest/gtest.h>

#include <cmath>

#include "core/stats/power.h"
#include "core/util/error.h"

namespace mtg::stats {
namespace {

TEST(NormalQuantile, MatchesTheTabulatedValues) {
  EXPECT_NEAR(normal_quantile(0.975), 1.959963984540054, 1e-11);
  EXPECT_NEAR(normal_quantile(0.8), 0.8416212335729143, 1e-11);
  EXPECT_NEAR(normal_quantile(0.9), 1.2815515655446004, 1e-11);
  EXPECT_NEAR(normal_quantile(0.995), 2.5758293035489004, 1e-11);
  EXPECT_NEAR(normal_quantile(0.5), 0.0, 1e-12);
  EXPECT_NEAR(normal_quantile(0.025), -1.959963984540054, 1e-11);
  EXPECT_THROW(normal_quantile(0.0), Error);
  EXPECT_THROW(normal_quantile(1.0), Error);
}

// Connor (1987): n = (z_{1-a/2} sqrt(psi) + z_{1-b} sqrt(psi - d^2))^2 / d^2. The table was computed
// by hand, independently of this code (Python's statistics.NormalDist for the quantiles).
TEST(McNemarSize, MatchesAHandComputedTable) {
  struct Row {
    double d, psi, alpha, power, exact;
    std::int64_t n;
  };
  const Row table[] = {
      {0.10, 0.30, 0.05, 0.80, 233.09453820467377, 234},
      {0.10, 0.20, 0.05, 0.80, 154.59856956021096, 155},
      {0.05, 0.10, 0.05, 0.80, 311.58687517566733, 312},
      {0.20, 0.40, 0.05, 0.90, 100.85391558129022, 101},
      {0.15, 0.25, 0.01, 0.80, 126.8390101880877, 127},
  };
  for (const Row& r : table) {
    const McNemarSize s = mcnemar_pairs_needed({r.d, r.psi, r.alpha, r.power});
    EXPECT_NEAR(s.exact, r.exact, 1e-6) << r.d << " " << r.psi;
    EXPECT_EQ(s.pairs, r.n) << r.d << " " << r.psi;
  }
}

TEST(McNemarSize, MoreDisagreementOrASmallerDifferenceNeedsMoreTasks) {
  const auto n = [](double d, double psi) { return mcnemar_pairs_needed({d, psi, 0.05, 0.8}).pairs; };
  EXPECT_LT(n(0.10, 0.2), n(0.10, 0.4));
  EXPECT_LT(n(0.20, 0.3), n(0.10, 0.3));
  // All discordant pairs one way (psi = d): the smallest sample for that difference.
  EXPECT_EQ(n(0.5, 0.5), static_cast<std::int64_t>(std::ceil(std::pow(1.959963984540054 * std::sqrt(0.5) +
                                                                       0.8416212335729143 * std::sqrt(0.25), 2) / 0.25)));
}

TEST(McNemarSize, InputsOutOfRangeAreNamed) {
  try {
    (void)mcnemar_pairs_needed({0.2, 0.1, 0.05, 0.8});
    ADD_FAILURE() << "a discordance below the difference was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("discordance"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)mcnemar_pairs_needed({0.0, 0.3, 0.05, 0.8}), Error);
  EXPECT_THROW((void)mcnemar_pairs_needed({0.1, 0.3, 0.0, 0.8}), Error);
  EXPECT_THROW((void)mcnemar_pairs_needed({0.1, 0.3, 0.05, 1.0}), Error);
  EXPECT_THROW((void)mcnemar_pairs_needed({0.1, 1.5, 0.05, 0.8}), Error);
}

}  // namespace
}  // namespace mtg::stats
