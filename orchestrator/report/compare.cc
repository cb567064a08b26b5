#include "orchestrator/report/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "core/stats/paired.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/rng.h"
#include "orchestrator/run/marks.h"
#include "orchestrator/run/provenance.h"
#include "orchestrator/run/run_plan.h"

namespace mtg::orchestrator {
namespace {

constexpr double kAlpha = 0.05;
constexpr std::uint64_t kCompareSeed = 0x6d74672d70616972ull;  // "mtg-pair": intervals are part of the output
constexpr std::size_t kFlipsListed = 200;                       // per kind; the counts are always whole
constexpr std::size_t kFlipsPrinted = 10;                       // in the text

struct Pair {
  const EpisodeRow* a;
  const EpisodeRow* b;
};

// (task, repeat) -> scored episode. The repeat comes from the plan's layout when known, so an
// episode given up or never run does not shift the later tries of its task; else the k-th row of
// a task (scored or not) is repeat k.
using PairKey = std::pair<std::string, std::int64_t>;  // task id, repeat

std::map<PairKey, const EpisodeRow*> by_task_and_repeat(const CompareSide& side) {
  std::map<PairKey, const EpisodeRow*> out;
  std::map<std::string, std::int64_t> seen;
  for (const EpisodeRow& r : side.rows) {  // rows come in episode order
    if (r.agent != side.agent) continue;
    const std::int64_t counted = seen[r.task_id]++;
    if (r.status != "scored") continue;
    out[{r.task_id, side.per_repeat > 0 ? r.episode_id.value() / side.per_repeat : counted}] = &r;
  }
  return out;
}

// A side's excluded episodes of its agent: how many, why, and the (task, repeat) each held. The
// repeat is known from the plan's layout only (per_repeat); without it a task's excluded episode
// is matched to every repeat.
struct Excluded {
  std::int64_t episodes = 0;
  std::map<std::string, std::int64_t> reasons;
  std::set<PairKey> keys;
  std::set<std::string> tasks;  // when the repeat is unknown
};

Excluded excluded_of(const CompareSide& side) {
  Excluded out;
  for (const ExcludedRow& x : side.excluded) {
    if (x.row.agent != side.agent || x.row.status != "scored") continue;
    ++out.episodes;
    ++out.reasons[x.reason];
    if (side.per_repeat > 0) {
      out.keys.insert({x.row.task_id, x.row.episode_id.value() / side.per_repeat});
    } else {
      out.tasks.insert(x.row.task_id);
    }
  }
  return out;
}

bool holds(const Excluded& e, const PairKey& key) { return e.keys.count(key) != 0 || e.tasks.count(key.first) != 0; }

nlohmann::json excluded_json(const Excluded& e) {
  return {{"episodes", e.episodes}, {"reasons", e.reasons}};
}

double round1(double v) { return std::round(v * 10.0) / 10.0; }

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(round1(v)) : nlohmann::json(nullptr); }

nlohmann::json level_json(const std::vector<Pair>& pairs, const std::string& seed_key) {
  std::vector<double> sa, sb, ia, ib;
  std::int64_t only_a = 0, only_b = 0;
  for (const Pair& p : pairs) {
    sa.push_back(p.a->success ? 100.0 : 0.0);
    sb.push_back(p.b->success ? 100.0 : 0.0);
    ia.push_back(p.a->ip);
    ib.push_back(p.b->ip);
    only_a += p.a->success && !p.b->success;
    only_b += !p.a->success && p.b->success;
  }
  const std::uint64_t seed = derive_seed(kCompareSeed, fnv1a64(seed_key));
  const stats::PairedDifference sr = stats::paired_difference(sa, sb, derive_seed(seed, 1));
  const stats::PairedDifference ip = stats::paired_difference(ia, ib, derive_seed(seed, 2));
  // A spread of zero (every pair alike) gives no detectable-difference figure, not "0 points".
  auto detectable = [](const stats::PairedDifference& d) { return d.detectable > 0.0 ? d.detectable : NAN; };
  return {{"pairs", static_cast<std::int64_t>(pairs.size())},
          {"sr_a", round1(stats::mean(sa))},
          {"sr_b", round1(stats::mean(sb))},
          {"sr_diff", round1(sr.mean)},
          {"sr_diff_ci", {round1(sr.interval.low), round1(sr.interval.high)}},
          {"only_a", only_a},
          {"only_b", only_b},
          {"sr_p", stats::mcnemar_exact_p(only_a, only_b)},
          {"sr_detectable", number_or_null(detectable(sr))},
          {"ip_a", round1(stats::mean(ia))},
          {"ip_b", round1(stats::mean(ib))},
          {"ip_diff", round1(ip.mean)},
          {"ip_diff_ci", {round1(ip.interval.low), round1(ip.interval.high)}},
          {"ip_p", ip.p},
          {"ip_detectable", number_or_null(detectable(ip))}};
}

nlohmann::json flip_json(const Pair& p) {
  return {{"task", p.a->task_id}, {"level", p.a->level}, {"episode_a", p.a->episode_id.value()},
          {"episode_b", p.b->episode_id.value()}};
}

nlohmann::json compare_one(const CompareSide& a, const CompareSide& b) {
  const auto left = by_task_and_repeat(a), right = by_task_and_repeat(b);
  std::map<std::string, std::vector<Pair>> by_level;
  std::vector<Pair> all;
  nlohmann::json regressions = nlohmann::json::array(), improvements = nlohmann::json::array();
  std::int64_t n_regressions = 0, n_improvements = 0;
  for (const auto& [key, ra] : left) {
    const auto it = right.find(key);
    if (it == right.end()) continue;
    const Pair p{ra, it->second};
    all.push_back(p);
    by_level[std::to_string(ra->level)].push_back(p);
    if (ra->success != p.b->success) {
      auto& list = ra->success ? regressions : improvements;
      (ra->success ? n_regressions : n_improvements) += 1;
      if (list.size() < kFlipsListed) list.push_back(flip_json(p));
    }
  }
  const std::string label = a.run + "/" + a.agent + " vs " + b.run + "/" + b.agent;
  if (all.empty()) {
    throw Error(label + ": no task ran on both sides (" + std::to_string(left.size()) + " and " +
                std::to_string(right.size()) + " scored episodes); pairs need the same task ids");
  }
  nlohmann::json c;
  c["a"] = {{"run", a.run}, {"agent", a.agent}};
  c["b"] = {{"run", b.run}, {"agent", b.agent}};
  c["pairs"] = static_cast<std::int64_t>(all.size());
  c["unpaired_a"] = static_cast<std::int64_t>(left.size() - all.size());
  c["unpaired_b"] = static_cast<std::int64_t>(right.size() - all.size());
  // Exclusions in plain sight (issue 55): what a person took out of each side, and which
  // episodes of one side are unpaired because their partner on the other was taken out.
  const Excluded out_a = excluded_of(a), out_b = excluded_of(b);
  c["excluded_a"] = excluded_json(out_a);
  c["excluded_b"] = excluded_json(out_b);
  std::int64_t a_lost = 0, b_lost = 0;
  for (const auto& [key, row] : left) a_lost += right.count(key) == 0 && holds(out_b, key) ? 1 : 0;
  for (const auto& [key, row] : right) b_lost += left.count(key) == 0 && holds(out_a, key) ? 1 : 0;
  c["unpaired_a_excluded_in_b"] = a_lost;
  c["unpaired_b_excluded_in_a"] = b_lost;
  const std::string seed_key = a.agent + " vs " + b.agent + "/";  // not the runs' names (see compare.h)
  for (const auto& [level, pairs] : by_level) c["levels"][level] = level_json(pairs, seed_key + level);
  c["levels"]["all"] = level_json(all, seed_key + "all");
  c["regressions"] = regressions;
  c["improvements"] = improvements;
  c["regression_count"] = n_regressions;
  c["improvement_count"] = n_improvements;
  return c;
}

// Holm within each family: one level and one measure, across the comparisons made.
void adjust_by_holm(nlohmann::json& comparisons) {
  std::map<std::string, std::vector<nlohmann::json*>> families;
  for (auto& c : comparisons) {
    for (auto& [level, l] : c["levels"].items()) families[level].push_back(&l);
  }
  for (auto& [level, members] : families) {
    for (const std::string measure : {"sr", "ip"}) {
      std::vector<double> p;
      for (const auto* m : members) p.push_back((*m)[measure + "_p"].get<double>());
      const std::vector<double> adjusted = stats::holm_adjusted(p);
      for (std::size_t i = 0; i < members.size(); ++i) (*members[i])[measure + "_p_holm"] = adjusted[i];
    }
  }
}

std::string p_text(double p) {
  char buf[32];
  if (p < 0.001) {
    std::snprintf(buf, sizeof buf, "%.1e", p);
  } else {
    std::snprintf(buf, sizeof buf, "%.3f", p);
  }
  return buf;
}

std::string signed1(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.1f", v);
  return buf;
}

std::string ci_text(const nlohmann::json& ci) {
  return "[" + signed1(ci[0].get<double>()) + ", " + signed1(ci[1].get<double>()) + "]";
}

std::string verdict(const nlohmann::json& l, const std::string& measure, const std::string& unit, double alpha) {
  const double p = l[measure + "_p_holm"].get<double>();
  const double diff = l[measure + "_diff"].get<double>();
  std::string out = measure == "sr" ? "SR: " : "IP: ";
  if (p < alpha) {
    out += std::string(diff < 0 ? "B is lower" : "B is higher") + " by " + signed1(diff).substr(1) + unit +
           ", significant (p " + p_text(p) + " after Holm)";
  } else {
    out += "not significant (p " + p_text(p) + " after Holm): these pairs cannot tell A and B apart";
    const auto& d = l[measure + "_detectable"];
    if (!d.is_null()) out += "; a difference of about " + signed1(d.get<double>()).substr(1) + unit + " would show (80 % power)";
  }
  return out;
}

}  // namespace

nlohmann::json compare_sides(const std::vector<CompareSide>& baselines, const std::vector<CompareSide>& candidates) {
  MTG_DEMAND(baselines.size() == candidates.size(), "compare_sides needs a baseline for each candidate");
  nlohmann::json out;
  out["alpha"] = kAlpha;
  out["comparisons"] = nlohmann::json::array();
  for (std::size_t i = 0; i < baselines.size(); ++i) out["comparisons"].push_back(compare_one(baselines[i], candidates[i]));
  adjust_by_holm(out["comparisons"]);
  return out;
}

nlohmann::json compare_runs(const RunRows& a, const RunRows* b, const std::string& agent, const std::string& baseline) {
  auto agents_of = [](const std::vector<EpisodeRow>& rows) {
    std::vector<std::string> agents;  // in the order they first ran: the run's own order
    for (const auto& r : rows) {
      if (std::find(agents.begin(), agents.end(), r.agent) == agents.end()) agents.push_back(r.agent);
    }
    return agents;
  };
  auto has = [](const std::vector<std::string>& agents, const std::string& x) {
    return std::find(agents.begin(), agents.end(), x) != agents.end();
  };
  const auto agents_a = agents_of(a.rows);
  std::vector<CompareSide> baselines, candidates;
  if (b != nullptr) {
    if (!baseline.empty()) throw Error("a baseline agent chooses within one run; with two runs, name the agent to compare");
    const auto agents_b = agents_of(b->rows);
    for (const std::string& x : agents_a) {
      if (!has(agents_b, x) || (!agent.empty() && x != agent)) continue;
      baselines.push_back({a.name, x, a.rows, a.per_repeat, a.excluded});
      candidates.push_back({b->name, x, b->rows, b->per_repeat, b->excluded});
    }
    if (baselines.empty()) {
      throw Error(agent.empty() ? "no agent ran in both " + a.name + " and " + b->name
                                : "agent " + agent + ": not an agent of both " + a.name + " and " + b->name);
    }
  } else {
    if (agents_a.size() < 2) throw Error(a.name + ": one agent only; give a second run to compare with");
    const std::string base = baseline.empty() ? agents_a.front() : baseline;
    if (!has(agents_a, base)) throw Error("baseline " + base + ": not an agent of " + a.name);
    if (!agent.empty() && (!has(agents_a, agent) || agent == base)) {
      throw Error("agent " + agent + ": not an agent of " + a.name + " other than the baseline " + base);
    }
    for (const std::string& x : agents_a) {
      if (x == base || (!agent.empty() && x != agent)) continue;
      baselines.push_back({a.name, base, a.rows, a.per_repeat, a.excluded});
      candidates.push_back({a.name, x, a.rows, a.per_repeat, a.excluded});
    }
  }
  nlohmann::json out = compare_sides(baselines, candidates);
  if (b != nullptr && !a.task_set.empty() && !b->task_set.empty() && a.task_set != b->task_set) {
    out["warning"] = a.name + " and " + b->name + " ran different task sets (" + a.task_set + "; " + b->task_set +
                     "): a task id may name another task in each";
  }
  return out;
}

RunRows run_rows(std::string name, const std::vector<EpisodeRow>& all, const std::map<bus::EpisodeId, EpisodeMarks>& marks,
                 std::string task_set, std::int64_t per_repeat) {
  RunRows out{std::move(name), without_excluded(all, marks), {}, std::move(task_set), per_repeat};
  for (const EpisodeRow& r : all) {
    const auto m = marks.find(r.episode_id);
    if (m != marks.end() && m->second.excluded) out.excluded.push_back({r, m->second.exclusion_reason});
  }
  return out;
}

RunRows load_run_rows(const std::filesystem::path& dir, const std::string& name) {
  if (!std::filesystem::exists(dir / "results.sqlite")) throw Error(dir.string() + ": not a run folder (no results.sqlite)");
  RunRows out = run_rows(name, read_results(dir / "results.sqlite"), current_marks(read_marks(dir)), "", 0);
  if (std::filesystem::exists(dir / "plan.json")) {
    const RunPlan plan = load_plan(dir);
    out.task_set = task_set_identity(plan.provenance);
    out.per_repeat = static_cast<std::int64_t>(plan.episodes.size()) / std::max(1, plan.repeat);
  }
  return out;
}

std::string compare_text(const nlohmann::json& comparison) {
  std::ostringstream o;
  const double alpha = comparison["alpha"].get<double>();
  if (comparison.contains("warning")) o << "warning: " << comparison["warning"].get<std::string>() << "\n";
  const std::size_t family = comparison["comparisons"].size();
  for (const auto& c : comparison["comparisons"]) {
    o << "B " << c["b"]["run"].get<std::string>() << "/" << c["b"]["agent"].get<std::string>() << " against A "
      << c["a"]["run"].get<std::string>() << "/" << c["a"]["agent"].get<std::string>() << ": " << c["pairs"]
      << " paired episodes";
    if (c["unpaired_a"].get<std::int64_t>() + c["unpaired_b"].get<std::int64_t>() > 0) {
      o << " (" << c["unpaired_a"] << " of A and " << c["unpaired_b"] << " of B without a partner, left out";
      const std::int64_t a_lost = c.value("unpaired_a_excluded_in_b", std::int64_t{0});
      const std::int64_t b_lost = c.value("unpaired_b_excluded_in_a", std::int64_t{0});
      if (a_lost > 0) o << "; " << a_lost << " of A's because B's episode was excluded";
      if (b_lost > 0) o << "; " << b_lost << " of B's because A's episode was excluded";
      o << ")";
    }
    o << "; differences are B - A, 95 % intervals, p after Holm over " << family << " comparison"
      << (family == 1 ? "" : "s") << "\n";
    for (const char* side : {"a", "b"}) {
      const nlohmann::json x = c.value(std::string("excluded_") + side, nlohmann::json::object());
      if (x.value("episodes", std::int64_t{0}) == 0) continue;
      o << "  excluded by a person from " << (side[0] == 'a' ? "A" : "B") << ": " << x["episodes"] << " episode(s)";
      std::string why;
      for (const auto& [reason, n] : x["reasons"].items()) {
        why += (why.empty() ? "" : "; ") + std::to_string(n.get<std::int64_t>()) + " \"" + reason + "\"";
      }
      o << " (" << why << "), outside every figure below\n";
    }
    char line[512];
    std::snprintf(line, sizeof line, "  %-6s %6s %7s %7s  %-24s %8s   %6s %6s  %-24s %8s\n", "level", "pairs", "SR A",
                  "SR B", "SR B-A [95 % CI]", "McNemar", "IP A", "IP B", "IP B-A [95 % CI]", "perm.");
    o << line;
    for (const auto& [level, l] : c["levels"].items()) {
      std::snprintf(line, sizeof line, "  %-6s %6lld %7.1f %7.1f  %-24s %8s   %6.1f %6.1f  %-24s %8s\n",
                    level == "all" ? "all" : ("L" + level).c_str(), static_cast<long long>(l["pairs"].get<std::int64_t>()),
                    l["sr_a"].get<double>(), l["sr_b"].get<double>(),
                    (signed1(l["sr_diff"].get<double>()) + " " + ci_text(l["sr_diff_ci"])).c_str(),
                    p_text(l["sr_p_holm"].get<double>()).c_str(), l["ip_a"].get<double>(), l["ip_b"].get<double>(),
                    (signed1(l["ip_diff"].get<double>()) + " " + ci_text(l["ip_diff_ci"])).c_str(),
                    p_text(l["ip_p_holm"].get<double>()).c_str());
      o << line;
    }
    const auto& all = c["levels"]["all"];
    o << "  " << verdict(all, "sr", " points", alpha) << "\n  " << verdict(all, "ip", " points", alpha) << "\n";
    for (const auto& [kind, key, count] : {std::tuple{"regressions (A succeeded, B failed)", "regressions", "regression_count"},
                                          std::tuple{"improvements (B succeeded, A failed)", "improvements", "improvement_count"}}) {
      o << "  " << c[count] << " " << kind << (c[count].get<std::int64_t>() > 0 ? ":" : "") << "\n";
      std::size_t shown = 0;
      for (const auto& f : c[key]) {
        if (shown++ == kFlipsPrinted) {
          o << "    ... (--json lists up to 200 of each)\n";
          break;
        }
        o << "    " << f["task"].get<std::string>() << "  episodes " << f["episode_a"] << " / " << f["episode_b"] << "\n";
      }
    }
  }
  return o.str();
}

}  // namespace mtg::orchestrator
