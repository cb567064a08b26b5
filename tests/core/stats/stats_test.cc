// Reference values: Wilson intervals as tabulated by Newcombe (1998, Table I) and recomputed by
// hand; exact McNemar p-values from the binomial distribution; Holm's procedure worked by hand;
// the sign-flip test enumerated by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "core/stats/intervals.h"
#include "core/stats/paired.h"
#include "core/stats/repeats.h"

namespace mtg::stats {
namespace {

TEST(Wilson, MatchesTheTabulatedIntervals) {
  const Interval five_of_six = wilson_interval(5, 6);  // a person's 5 of 6: SR 83 %, 44–97 %
  EXPECT_NEAR(five_of_six.low, 0.436497, 1e-6);
  EXPECT_NEAR(five_of_six.high, 0.969947, 1e-6);
  const Interval none_of_ten = wilson_interval(0, 10);
  EXPECT_EQ(none_of_ten.low, 0.0);
  EXPECT_NEAR(none_of_ten.high, 0.277533, 1e-6);
  const Interval all_of_ten = wilson_interval(10, 10);
  EXPECT_EQ(all_of_ten.high, 1.0);
  EXPECT_NEAR(all_of_ten.low, 1.0 - 0.277533, 1e-6);
  const Interval paper_like = wilson_interval(62, 100);
  EXPECT_NEAR(paper_like.low, 0.522098, 1e-6);
  EXPECT_NEAR(paper_like.high, 0.709024, 1e-6);
  EXPECT_EQ(wilson_interval(0, 0), Interval{});
}

TEST(Wilson, AnAverageOfLevelsUsesItsEffectiveSize) {
  // Equal levels: the pooled interval. 40 + 40 + 40 all successes = Wilson(120, 120).
  const std::vector<Tally> equal{{40, 40}, {40, 40}, {40, 40}};
  EXPECT_NEAR(stratified_wilson_interval(equal).low, wilson_interval(120, 120).low, 1e-12);
  EXPECT_EQ(stratified_wilson_interval(equal).high, 1.0);
  // Unequal levels: 9/10 and 1/2 average 0.7 with n_eff = 4 / (1/10 + 1/2) = 6.67.
  const Interval unequal = stratified_wilson_interval({{9, 10}, {1, 2}, {0, 0}});
  EXPECT_EQ(unequal, wilson_interval_of(0.7, 4.0 / 0.6));
  EXPECT_LT(unequal.low, 0.7);
  EXPECT_GT(unequal.high, 0.7);
  EXPECT_EQ(stratified_wilson_interval({}), Interval{});
}

TEST(Quantile, InterpolatesLikeRAndNumPy) {
  const std::vector<double> v{1, 2, 3, 4};
  EXPECT_DOUBLE_EQ(quantile_of_sorted(v, 0.25), 1.75);
  EXPECT_DOUBLE_EQ(quantile_of_sorted(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(quantile_of_sorted(v, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(quantile_of_sorted({7}, 0.975), 7.0);
}

TEST(Bootstrap, IsSeededAndBracketsTheMean) {
  std::vector<double> values;
  for (int i = 0; i < 100; ++i) values.push_back(i % 2 ? 100.0 : 0.0);  // a coin: mean 50, se 5
  const Interval a = bootstrap_mean_interval(values, 11), b = bootstrap_mean_interval(values, 11);
  EXPECT_EQ(a, b) << "the same results print the same interval";
  // The normal approximation gives 50 ± 9.8; the percentile bootstrap lands within a point of it.
  EXPECT_NEAR(a.low, 40.2, 1.5);
  EXPECT_NEAR(a.high, 59.8, 1.5);
  EXPECT_EQ(bootstrap_mean_interval({25.0, 25.0, 25.0}, 1), (Interval{25.0, 25.0}));
  EXPECT_EQ(bootstrap_mean_interval({40.0}, 1), (Interval{40.0, 40.0}));
}

TEST(Bootstrap, AMeanOfLevelMeansResamplesEachLevelOnItsOwn) {
  // One level always 100, one always 0: the average is 50 with no uncertainty at all, however
  // unequal the levels' sizes; pooling the episodes would have given 91 and a spread.
  const std::vector<std::vector<double>> strata{std::vector<double>(10, 100.0), std::vector<double>(1, 0.0), {}};
  EXPECT_EQ(bootstrap_mean_of_means_interval(strata, 3), (Interval{50.0, 50.0}));
}

TEST(McNemar, ExactPValuesFromTheBinomial) {
  EXPECT_NEAR(mcnemar_exact_p(1, 9), 2.0 * 11.0 / 1024.0, 1e-15);  // 2·P[X <= 1], X ~ Bin(10, 1/2)
  EXPECT_NEAR(mcnemar_exact_p(9, 1), 2.0 * 11.0 / 1024.0, 1e-15);
  EXPECT_NEAR(mcnemar_exact_p(0, 5), 0.0625, 1e-15);
  EXPECT_DOUBLE_EQ(mcnemar_exact_p(3, 3), 1.0);
  EXPECT_DOUBLE_EQ(mcnemar_exact_p(0, 0), 1.0);
  // Large counts stay finite and small: 0 of 2,000 discordant pairs for A.
  EXPECT_LT(mcnemar_exact_p(0, 2000), 1e-300);
  EXPECT_GE(mcnemar_exact_p(0, 2000), 0.0);
}

TEST(Holm, StepsDownAndKeepsTheOrderGiven) {
  const std::vector<double> adjusted = holm_adjusted({0.01, 0.04, 0.03, 0.005});
  ASSERT_EQ(adjusted.size(), 4u);
  EXPECT_DOUBLE_EQ(adjusted[0], 0.03);  // 2nd smallest x 3
  EXPECT_DOUBLE_EQ(adjusted[1], 0.06);  // 4th x 1 = 0.04, raised to the running maximum
  EXPECT_DOUBLE_EQ(adjusted[2], 0.06);  // 3rd x 2
  EXPECT_DOUBLE_EQ(adjusted[3], 0.02);  // smallest x 4
  EXPECT_EQ(holm_adjusted({0.6, 0.7}), (std::vector<double>{1.0, 1.0}));
  EXPECT_TRUE(holm_adjusted({}).empty());
}

TEST(PairedDifference, SignFlipsAreEnumeratedWhenFew) {
  // d = 1, 2, 3: of the 8 sign patterns only +++ and --- reach |sum| = 6.
  const PairedDifference d = paired_difference({0, 0, 0}, {1, 2, 3}, 5);
  EXPECT_EQ(d.pairs, 3);
  EXPECT_DOUBLE_EQ(d.mean, 2.0);
  EXPECT_DOUBLE_EQ(d.p, 0.25);
  EXPECT_LE(d.interval.low, d.mean);
  EXPECT_GE(d.interval.high, d.mean);
  // No difference at all: p = 1, nothing detectable from no spread.
  const PairedDifference same = paired_difference({50, 25}, {50, 25}, 5);
  EXPECT_DOUBLE_EQ(same.p, 1.0);
  EXPECT_DOUBLE_EQ(same.mean, 0.0);
}

TEST(PairedDifference, TheDetectableDifferenceFollowsTheSpread) {
  // d = 0, 100, 0, 100: s_d = 57.735; (1.960 + 0.842) x 57.735 / 2 = 80.87.
  const PairedDifference d = paired_difference({0, 0, 0, 0}, {0, 100, 0, 100}, 5);
  EXPECT_NEAR(d.detectable, 80.8748, 1e-3);
  EXPECT_TRUE(std::isnan(paired_difference({1}, {2}, 5).detectable));
}

TEST(PairedDifference, ManyPairsUseSeededMonteCarlo) {
  std::vector<double> a(200, 0.0), b(200, 0.0);
  for (int i = 0; i < 200; i += 4) b[static_cast<std::size_t>(i)] = 100.0;  // B better on a quarter
  const PairedDifference d = paired_difference(a, b, 9);
  EXPECT_DOUBLE_EQ(d.mean, 25.0);
  EXPECT_EQ(d.p, paired_difference(a, b, 9).p);
  EXPECT_LT(d.p, 0.001);  // 50 of 200 one way, none the other
  EXPECT_GT(d.p, 0.0) << "a Monte Carlo p is never 0";
  EXPECT_GT(d.interval.low, 15.0);
  EXPECT_LT(d.interval.high, 35.0);
}

TEST(Repeats, PassAtKAndPassHatKFromAllTheTries) {
  // 2 successes in 5: pass@1 = 2/5; pass@2 = 1 - C(3,2)/C(5,2) = 1 - 3/10; pass^2 = C(2,2)/C(5,2) = 1/10.
  EXPECT_DOUBLE_EQ(pass_at_k(5, 2, 1), 0.4);
  EXPECT_DOUBLE_EQ(pass_at_k(5, 2, 2), 0.7);
  EXPECT_DOUBLE_EQ(pass_hat_k(5, 2, 1), 0.4);
  EXPECT_NEAR(pass_hat_k(5, 2, 2), 0.1, 1e-15);
  EXPECT_DOUBLE_EQ(pass_hat_k(5, 2, 3), 0.0);  // three successes out of two: never
  EXPECT_DOUBLE_EQ(pass_at_k(5, 2, 4), 1.0);   // four tries among five always include a success
  EXPECT_DOUBLE_EQ(pass_at_k(3, 0, 3), 0.0);
  EXPECT_DOUBLE_EQ(pass_hat_k(3, 3, 3), 1.0);
  EXPECT_GT(pass_at_k(400, 1, 200), 0.49);     // large n: no overflow
}

}  // namespace
}  // namespace mtg::stats
