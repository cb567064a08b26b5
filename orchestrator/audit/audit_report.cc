#include "orchestrator/audit/audit_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/stats/intervals.h"

namespace mtg::orchestrator::audit {
namespace {

void finish(LevelRow& r) {
  r.validity = r.answered > 0 ? static_cast<double>(r.valid) / r.answered : 0.0;
  const stats::Interval ci = stats::wilson_interval(r.valid, r.answered);
  r.low = ci.low;
  r.high = ci.high;
  r.accuracy = r.picks > 0 ? static_cast<double>(r.right) / r.picks : 0.0;
}

nlohmann::json row_json(const LevelRow& r) {
  auto pct = [](double x) { return std::round(x * 1000.0) / 10.0; };
  return {{"level", r.level},          {"sampled", r.sampled},   {"answered", r.answered},
          {"valid", r.valid},          {"validity", pct(r.validity)}, {"ci95", {pct(r.low), pct(r.high)}},
          {"picks", r.picks},          {"right", r.right},        {"accuracy", pct(r.accuracy)}};
}

}  // namespace

bool right_pick(const std::string& pick, const std::string& truth) {
  if (pick.empty()) return false;
  std::istringstream keys(truth);
  std::string key;
  while (keys >> key) {
    if (key == pick) return true;
  }
  return false;
}

AuditReport make_report(const std::vector<Item>& items, const std::map<std::string, std::map<int, Answer>>& by_rater) {
  // Every rater's answers together: each answer counts once, each rater's misses named.
  std::map<int, Answer> none;
  AuditReport report = make_report(items, none);
  std::map<int, LevelRow> rows;
  for (const LevelRow& r : report.levels) rows[r.level] = {r.level};
  for (const auto& [rater, answers] : by_rater) {
    const AuditReport one = make_report(items, answers);
    report.per_rater[rater] = one;
    report.raters.push_back(rater);
    for (const LevelRow& r : one.levels) {
      LevelRow& sum = rows[r.level];
      sum.level = r.level;
      sum.sampled += r.sampled;
      sum.answered += r.answered;
      sum.valid += r.valid;
      sum.picks += r.picks;
      sum.right += r.right;
    }
    for (Miss m : one.misses) {
      m.cause = rater + ": " + m.cause;
      report.misses.push_back(std::move(m));
    }
  }
  if (!by_rater.empty()) {
    report.levels.clear();
    report.all = {};
    for (auto& [level, r] : rows) {
      finish(r);
      report.levels.push_back(r);
      report.all.sampled += r.sampled;
      report.all.answered += r.answered;
      report.all.valid += r.valid;
      report.all.picks += r.picks;
      report.all.right += r.right;
    }
    finish(report.all);
  }
  // How alike each pair judged the tasks both answered.
  for (auto a = by_rater.begin(); a != by_rater.end(); ++a) {
    for (auto b = std::next(a); b != by_rater.end(); ++b) {
      std::vector<std::string> valid_a, valid_b, picks_a, picks_b;
      for (const Item& item : items) {
        const auto x = a->second.find(item.index), y = b->second.find(item.index);
        if (x == a->second.end() || y == b->second.end()) continue;
        valid_a.push_back(x->second.valid ? "valid" : "invalid");
        valid_b.push_back(y->second.valid ? "valid" : "invalid");
        for (const auto& [question, truth] : item.truth.items()) {
          const auto px = x->second.picks.find(question), py = y->second.picks.find(question);
          if (px == x->second.picks.end() || py == y->second.picks.end()) continue;
          auto judged = [&](const std::string& pick) {
            return pick.empty() ? "unknown" : right_pick(pick, truth.get<std::string>()) ? "right" : "wrong";
          };
          picks_a.push_back(judged(px->second));
          picks_b.push_back(judged(py->second));
        }
      }
      report.agreement.push_back({a->first, b->first, agreement(valid_a, valid_b), agreement(picks_a, picks_b)});
    }
  }
  return report;
}

AuditReport make_report(const std::vector<Item>& items, const std::map<int, Answer>& answers) {
  AuditReport report;
  std::map<int, LevelRow> rows;
  for (const Item& item : items) {
    LevelRow& r = rows[item.level];
    r.level = item.level;
    ++r.sampled;
    ++report.all.sampled;
    const auto it = answers.find(item.index);
    if (it == answers.end()) continue;
    const Answer& a = it->second;
    ++r.answered;
    ++report.all.answered;
    if (a.valid) {
      ++r.valid;
      ++report.all.valid;
    } else {
      std::string cause = "invalid: " + std::string(a.reason ? to_string(*a.reason) : "other");
      if (!a.note.empty()) cause += " (" + a.note + ")";
      report.misses.push_back({item.task_id, item.level, cause});
    }
    for (const auto& [question, truth] : item.truth.items()) {
      const auto pick = a.picks.find(question);
      if (pick == a.picks.end()) continue;  // not asked of this answer
      ++r.picks;
      ++report.all.picks;
      if (right_pick(pick->second, truth.get<std::string>())) {
        ++r.right;
        ++report.all.right;
      } else {
        report.misses.push_back({item.task_id, item.level,
                                 question + ": answered " + (pick->second.empty() ? "\"don't know\"" : pick->second) +
                                     ", it is " + truth.get<std::string>()});
      }
    }
  }
  for (auto& [level, r] : rows) {
    finish(r);
    report.levels.push_back(r);
  }
  finish(report.all);
  return report;
}

nlohmann::json AuditReport::to_json() const {
  nlohmann::json levels_json = nlohmann::json::array();
  for (const LevelRow& r : levels) levels_json.push_back(row_json(r));
  nlohmann::json misses_json = nlohmann::json::array();
  for (const Miss& m : misses) misses_json.push_back({{"task_id", m.task_id}, {"level", m.level}, {"cause", m.cause}});
  nlohmann::json agreement_json = nlohmann::json::array();
  auto agreed = [](const Agreement& x) {
    return nlohmann::json{{"questions", x.questions}, {"percent", std::round(x.percent * 10.0) / 10.0},
                          {"kappa", std::round(x.kappa * 1000.0) / 1000.0}};
  };
  for (const PairAgreement& p : agreement) {
    agreement_json.push_back({{"raters", {p.a, p.b}}, {"validity", agreed(p.validity)}, {"picks", agreed(p.picks)}});
  }
  nlohmann::json out = {{"levels", levels_json}, {"all", row_json(all)}, {"misses", misses_json},
                        {"paper_validity", {{"1", 93.8}, {"2", 98.4}, {"3", 92.3}, {"4", 74.1}}},
                        {"agreement", agreement_json}};
  if (!raters.empty()) out["raters"] = raters;
  if (!per_rater.empty()) {
    nlohmann::json each = nlohmann::json::object();
    for (const auto& [name, r] : per_rater) each[name] = r.to_json();
    out["per_rater"] = each;
  }
  return out;
}

std::string AuditReport::to_text() const {
  static const std::map<int, double> kPaper = {{1, 93.8}, {2, 98.4}, {3, 92.3}, {4, 74.1}};
  std::string out = "level  answered/sampled  valid  validity (95 % interval)   paper   identified right\n";
  char line[256];
  auto print = [&](const LevelRow& r, const std::string& name) {
    const auto paper = kPaper.find(r.level);
    char picks[64] = "none asked";  // "0/0 = 0.0 %" would read as all wrong
    if (r.picks > 0) std::snprintf(picks, sizeof picks, "%d/%d = %.1f %%", r.right, r.picks, 100 * r.accuracy);
    std::snprintf(line, sizeof line, "%-5s  %8d/%-7d  %5d  %6.1f %% (%5.1f-%5.1f %%)  %6s   %s\n", name.c_str(),
                  r.answered, r.sampled, r.valid, 100 * r.validity, 100 * r.low, 100 * r.high,
                  paper == kPaper.end() ? "" : (std::to_string(paper->second).substr(0, 4) + " %").c_str(), picks);
    out += line;
  };
  for (const LevelRow& r : levels) print(r, std::to_string(r.level));
  print(all, "all");
  for (const PairAgreement& p : agreement) {
    std::snprintf(line, sizeof line,
                  "%s / %s: validity %.1f %% alike over %d tasks (Cohen's kappa %.2f); picks %.1f %% alike over %d "
                  "questions (kappa %.2f)\n",
                  p.a.c_str(), p.b.c_str(), p.validity.percent, p.validity.questions, p.validity.kappa, p.picks.percent,
                  p.picks.questions, p.picks.kappa);
    out += line;
  }
  if (!misses.empty()) out += "misses:\n";
  for (const Miss& m : misses) out += "  " + m.task_id + " (level " + std::to_string(m.level) + "): " + m.cause + "\n";
  return out;
}

}  // namespace mtg::orchestrator::audit
