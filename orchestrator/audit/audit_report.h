#pragma once
// The paper's Table 2 from an audit's answers: per level, how many tasks the person judged valid,
// with a 95 % Wilson interval, and how often they picked the right number for each object the
// text names; every miss with its task and cause.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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

struct AuditReport {
  std::vector<LevelRow> levels;
  LevelRow all;  // level 0
  std::vector<Miss> misses;
  nlohmann::json to_json() const;
  std::string to_text() const;
};

/// 95 % Wilson score interval of k successes in n trials ({0, 0} for n = 0).
std::pair<double, double> wilson_interval(int k, int n);

AuditReport make_report(const std::vector<Item>& items, const std::map<int, Answer>& answers);

}  // namespace mtg::orchestrator::audit
