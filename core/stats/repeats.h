#pragma once
// Repeated episodes of one task (`mtg run --repeat N`): how often an agent gets a task right at
// least once in k tries, and every time in k tries (docs/statistics.md). With n episodes of a task
// and c successes among them, both are estimated without bias from all n, not from the first k:
//   pass@k = 1 - C(n - c, k) / C(n, k)   (Chen et al., 2021)
//   pass^k = C(c, k) / C(n, k)           (Yao et al., 2024, tau-bench)
// Requires 1 <= k <= n and 0 <= c <= n.

namespace mtg::stats {

double pass_at_k(int n, int c, int k);
double pass_hat_k(int n, int c, int k);

}  // namespace mtg::stats
