#pragma once
// The paper's Table 2 from an audit's answers: per level, how many tasks the person judged valid,
// with a 95 % Wilson interval, and how often they picked the right number for each object the
// text names; every miss with its task and cause.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/util/agreement.h"
#include "orchestrator/audit/audit_store.h"

namespace mtg::orchestrator::audit {

struct LevelRow {
  int level = 0;
  int sampled = 0;
  int answered = 0;
  int valid = 0;
  double validity = 0.0;          // valid / answered
  double low = 0.0, high = 0.0;   // 95 % Wilson interval of validity
  int picks = 0;                  // questions answered
  int right = 0;                  // ... with the right number
  double accuracy = 0.0;
};

struct Miss {
  std::string task_id;
  int level = 0;
  std::string cause;  // "invalid: occluded (note)", "p0.item: answered o3, it is o5", ...
};

/// How alike two raters judged the tasks both answered: validity, and whether each pick was
/// right, wrong or "don't know".
struct PairAgreement {
  std::string a, b;
  Agreement validity;
  Agreement picks;
};

struct AuditReport {
  std::vector<LevelRow> levels;
  LevelRow all;  // level 0
  std::vector<Miss> misses;
  std::vector<std::string> raters;  // whose answers are counted (every one once)
  std::map<std::string, AuditReport> per_rater;
  std::vector<PairAgreement> agreement;
  nlohmann::json to_json() const;
  std::string to_text() const;
};

/// Whether `pick` is one of the space-separated keys of `truth`.
bool right_pick(const std::string& pick, const std::string& truth);

/// One rater's report.
AuditReport make_report(const std::vector<Item>& items, const std::map<int, Answer>& answers);
/// Every rater's answers counted together, with pairwise agreement (percent, Cohen's kappa).
AuditReport make_report(const std::vector<Item>& items, const std::map<std::string, std::map<int, Answer>>& by_rater);

}  // namespace mtg::orchestrator::audit
