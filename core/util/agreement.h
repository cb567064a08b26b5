#pragma once
// How much two raters agree on the same questions: the share of equal answers and Cohen's kappa
// (agreement beyond what their own answer rates would give by chance). Answers are categories
// named by strings ("valid", "o3", "yes"); a question one rater skipped is left out by the caller.

#include <string>
#include <vector>

namespace mtg {

struct Agreement {
  int questions = 0;
  int equal = 0;
  double percent = 0.0;  // 100 * equal / questions
  /// Cohen's kappa: (p_o - p_e) / (1 - p_e); 1 when both raters always give the same single
  /// answer (p_e = 1), 0 when there are no questions.
  double kappa = 0.0;
};

/// `a[i]` and `b[i]` answer the same question. @throws mtg::Error when the sizes differ.
Agreement agreement(const std::vector<std::string>& a, const std::vector<std::string>& b);

}  // namespace mtg
