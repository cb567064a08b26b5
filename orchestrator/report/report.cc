#include "orchestrator/report/report.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

#include "agents/vlm/model_spec.h"
#include "core/episode/outcomes.h"
#include "core/stats/intervals.h"
#include "core/stats/repeats.h"
#include "core/util/hash.h"
#include "core/util/rng.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "core/util/text.h"
#include "orchestrator/report/sankey.h"

namespace mtg::orchestrator {
namespace {

// Fixed: intervals are part of the report's bytes (docs/statistics.md).
constexpr std::uint64_t kReportSeed = 0x6d74672d63693935ull;  // "mtg-ci95"
constexpr int kPaperLevels = 3;  // the paper's Table 3 averages Levels 1-3

double round1(double v) { return std::round(v * 10.0) / 10.0; }

// Bootstrap intervals are seeded by what they describe ("agent/level"), so a report is the same
// bytes every time it is made, and one group's interval does not move when another group grows.
std::uint64_t interval_seed(std::string_view group) { return derive_seed(kReportSeed, fnv1a64(group)); }

nlohmann::json interval_json(const stats::Interval& ci) { return nlohmann::json::array({round1(ci.low), round1(ci.high)}); }
nlohmann::json percent_interval_json(const stats::Interval& ci) { return interval_json({100.0 * ci.low, 100.0 * ci.high}); }

struct Acc {
  std::int64_t episodes = 0, successes = 0;
  std::vector<double> ips;          // per scored episode, in episode order
  void add(const EpisodeRow& r) {
    ++episodes;
    successes += r.success ? 1 : 0;
    ips.push_back(r.ip);
  }
  double sr() const { return episodes ? 100.0 * static_cast<double>(successes) / static_cast<double>(episodes) : 0.0; }
  double ip() const {
    return episodes ? std::accumulate(ips.begin(), ips.end(), 0.0) / static_cast<double>(episodes) : 0.0;
  }
  nlohmann::json json(std::string_view group) const {
    return {{"episodes", episodes},
            {"sr", round1(sr())},
            {"sr_ci", percent_interval_json(stats::wilson_interval(successes, episodes))},
            {"ip", round1(ip())},
            {"ip_ci", interval_json(stats::bootstrap_mean_interval(ips, interval_seed(group)))}};
  }
};

// The paper's "Avg": the mean of the per-level figures over Levels 1-3 (those the run has), not
// the pooled rate, so a level with more episodes weighs no more. SR's interval is Wilson's at the
// average's effective size; IP's resamples each level on its own.
nlohmann::json paper_average(const std::map<std::string, Acc>& by_level, const std::string& agent) {
  std::vector<std::string> levels;
  std::vector<std::vector<double>> ips;
  std::vector<stats::Tally> successes;
  double sr = 0.0, ip = 0.0;
  for (const auto& [level, acc] : by_level) {
    if (std::stoi(level) > kPaperLevels) continue;
    levels.push_back(level);
    ips.push_back(acc.ips);
    successes.push_back({acc.successes, acc.episodes});
    sr += acc.sr();
    ip += acc.ip();
  }
  if (levels.empty()) return nullptr;
  const double n = static_cast<double>(levels.size());
  return {{"levels", levels},
          {"sr", round1(sr / n)},
          {"sr_ci", percent_interval_json(stats::stratified_wilson_interval(successes))},
          {"ip", round1(ip / n)},
          {"ip_ci", interval_json(stats::bootstrap_mean_of_means_interval(ips, interval_seed(agent + "/avg/ip")))}};
}

// Per agent, when some task ran more than once (--repeat): pass@k and pass^k for k = 1 up to the
// fewest episodes any of its tasks has (so every task counts in every k), and how many tasks
// succeeded c times of n. Null without repeats.
nlohmann::json repeats_json(const std::map<std::string, std::pair<int, int>>& runs_and_successes) {
  int fewest = std::numeric_limits<int>::max(), most = 0;
  for (const auto& [task, nc] : runs_and_successes) {
    fewest = std::min(fewest, nc.first);
    most = std::max(most, nc.first);
  }
  if (most < 2) return nullptr;
  nlohmann::json at = nlohmann::json::array(), hat = nlohmann::json::array();
  for (int k = 1; k <= fewest; ++k) {
    double sum_at = 0.0, sum_hat = 0.0;
    for (const auto& [task, nc] : runs_and_successes) {
      sum_at += stats::pass_at_k(nc.first, nc.second, k);
      sum_hat += stats::pass_hat_k(nc.first, nc.second, k);
    }
    const auto tasks = static_cast<double>(runs_and_successes.size());
    at.push_back(round1(100.0 * sum_at / tasks));
    hat.push_back(round1(100.0 * sum_hat / tasks));
  }
  std::map<std::string, std::int64_t> k_of_n;  // "2/3" -> tasks
  for (const auto& [task, nc] : runs_and_successes) k_of_n[std::to_string(nc.second) + "/" + std::to_string(nc.first)] += 1;
  return {{"tasks", static_cast<std::int64_t>(runs_and_successes.size())},
          {"episodes_per_task", {fewest, most}},
          {"pass_at_k", at},
          {"pass_hat_k", hat},
          {"k_of_n", k_of_n}};
}

// What a model agent's calls cost, over every episode of the run (spending happens whether or
// not the episode was scored).
struct Usage {
  episode::EpisodeUsage total;
  // An endpoint of one's own (openai-compatible:<url>:<model>) has no price of its own: the
  // table's figure for it is a guess, not money spent.
  bool price_known = true;
  std::set<std::string> prompt_versions;  // every version used, not only the last
  void add(const EpisodeRow& r) {
    total.add(r.usage);
    if (!r.usage.prompt_version.empty()) prompt_versions.insert(r.usage.prompt_version);
  }
  nlohmann::json json() const {
    auto round6 = [](double v) { return std::round(v * 1e6) / 1e6; };
    const std::int64_t calls = total.model_calls;
    return {{"calls", calls},
            {"cache_hits", total.cache_hits},
            {"input_tokens", total.input_tokens},
            {"output_tokens", total.output_tokens},
            {"images", total.images_sent},
            {"cost_usd", round6(total.cost_usd)},
            {"spent_usd", round6(total.spent_usd)},
            {"price_known", price_known},
            {"mean_latency_ms", calls ? std::round(total.latency_ms / static_cast<double>(calls)) : 0.0},
            {"prompt_versions", prompt_versions}};
  }
};

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(1);
  o << std::fixed << v;
  return o.str();
}

}  // namespace

namespace {

// figures[key], then its interval between `open`, `dash` and `close` when the report has one.
std::string figure_with_interval(const nlohmann::json& figures, const std::string& key, const char* open,
                                 const char* dash, const char* close) {
  std::string out = fmt(figures[key].get<double>());
  if (figures.contains(key + "_ci")) {
    const auto& ci = figures[key + "_ci"];
    out += open + fmt(ci[0].get<double>()) + dash + fmt(ci[1].get<double>()) + close;
  }
  return out;
}

}  // namespace

std::string with_interval(const nlohmann::json& figures, const std::string& key) {
  return figure_with_interval(figures, key, " [", ", ", "]");
}

std::string with_interval_html(const nlohmann::json& figures, const std::string& key) {
  return figure_with_interval(figures, key, "<br><small class=ci>", "&ndash;", "</small>");
}

std::string repeats_text(const std::string& agent, const nlohmann::json& rep) {
  std::ostringstream o;
  const auto& n = rep["episodes_per_task"];
  o << agent << ": " << rep["tasks"] << " tasks, " << n[0] << (n[0] == n[1] ? "" : "–" + n[1].dump()) << " episodes each;";
  const std::size_t k_max = rep["pass_at_k"].size();
  for (std::size_t k = 1; k <= k_max; ++k) o << " pass@" << k << " " << fmt(rep["pass_at_k"][k - 1].get<double>());
  o << "; pass^" << k_max << " " << fmt(rep["pass_hat_k"][k_max - 1].get<double>()) << " (every try right); tasks by successes:";
  for (const auto& [kn, tasks] : rep["k_of_n"].items()) o << " " << kn << " " << tasks;
  return o.str();
}

std::string repeats_html(const nlohmann::json& report) {
  std::string h;
  for (const auto& [agent, a] : report["by_agent"].items()) {
    if (a.contains("repeats")) h += "<li>" + escape_markup(repeats_text(agent, a["repeats"])) + "</li>";
  }
  if (h.empty()) return h;
  return "<h2>Repeats</h2><ul>" + h +
         "</ul><p class=note>pass@k: the share of tasks an agent gets right at least once in k tries; pass^k: "
         "right in all k. Both estimated from every try of a task (docs/statistics.md).</p>";
}

std::string average_label(const nlohmann::json& levels) {
  if (!levels.is_array() || levels.empty()) return "";
  const std::string first = levels.front().get<std::string>(), last = levels.back().get<std::string>();
  return levels.size() == 1 ? "Avg (L" + first + ")" : "Avg (L" + first + "–" + last + ")";
}

std::string paper_average_label(const nlohmann::json& report) {
  nlohmann::json levels = nlohmann::json::array();
  for (const auto& [l, v] : report["by_level"].items()) {
    if (std::stoi(l) <= kPaperLevels) levels.push_back(l);
  }
  return average_label(levels);
}

nlohmann::json make_report(const std::vector<EpisodeRow>& all_rows, const std::string& run_id,
                           const std::map<bus::EpisodeId, EpisodeMarks>* marks) {
  const bool marked = marks != nullptr && !marks->empty();
  const std::vector<EpisodeRow> kept = marked ? without_excluded(all_rows, *marks) : std::vector<EpisodeRow>{};
  const std::vector<EpisodeRow>& rows = marked ? kept : all_rows;
  Acc all;
  std::map<std::string, Acc> by_level;
  std::map<std::string, Acc> by_agent;
  std::map<std::string, std::map<std::string, Acc>> by_agent_level;
  std::map<std::string, std::int64_t> causes, stages;
  std::map<std::string, std::map<std::string, std::int64_t>> causes_by_agent;
  std::int64_t errors = 0, in_tokens = 0, out_tokens = 0;
  double cost = 0.0;
  std::vector<SankeyFlow> flows;
  std::map<std::string, Usage> usage;
  std::map<std::string, std::map<std::string, std::pair<int, int>>> per_task;  // agent -> task -> (n, c)
  for (const EpisodeRow& r : rows) {
    // A person's or a replay's answers are not model calls: no tokens, no price (issue 52).
    if (r.usage.model_calls > 0 && vlm::is_model_spec(r.agent)) {
      usage[r.agent].add(r);
      usage[r.agent].price_known = r.agent.rfind("openai-compatible:", 0) != 0;
    }
    if (r.status != "scored") {
      ++errors;
      continue;
    }
    const std::string level = std::to_string(r.level);
    all.add(r);
    by_level[level].add(r);
    by_agent[r.agent].add(r);
    by_agent_level[r.agent][level].add(r);
    auto& [runs, successes] = per_task[r.agent][r.task_id];
    runs += 1;
    successes += r.success ? 1 : 0;
    stages[r.stage] += 1;
    if (!r.success) {
      causes[r.cause] += 1;
      causes_by_agent[r.agent][r.cause] += 1;
    }
    if (vlm::is_model_spec(r.agent)) {
      in_tokens += r.usage.input_tokens;
      out_tokens += r.usage.output_tokens;
      cost += r.usage.cost_usd;
    }
    flows.push_back({"Level " + level, r.stage, r.success ? "success" : r.cause, r.success ? "success" : "failure"});
  }
  nlohmann::json j;
  j["run"] = run_id;
  j["episodes"] = static_cast<std::int64_t>(rows.size());
  j["scored"] = all.episodes;
  j["errors"] = errors;
  const nlohmann::json totals = all.json("*");
  for (const char* key : {"sr", "sr_ci", "ip", "ip_ci"}) j[key] = totals[key];
  j["by_level"] = nlohmann::json::object();
  for (const auto& [l, acc] : by_level) j["by_level"][l] = acc.json("*/" + l);
  j["by_agent"] = nlohmann::json::object();
  for (const auto& [agent, acc] : by_agent) {
    nlohmann::json a = acc.json(agent);
    for (const auto& [l, la] : by_agent_level[agent]) a["by_level"][l] = la.json(agent + "/" + l);
    a["paper_avg"] = paper_average(by_agent_level[agent], agent);
    if (nlohmann::json rep = repeats_json(per_task[agent]); !rep.is_null()) a["repeats"] = std::move(rep);
    a["causes"] = causes_by_agent[agent];
    j["by_agent"][agent] = a;
  }
  j["causes"] = causes;
  j["stages"] = stages;
  j["tokens"] = {{"input", in_tokens}, {"output", out_tokens}};
  j["cost_usd"] = std::round(cost * 1e6) / 1e6;
  j["sankey"] = sankey_graph(flows);
  if (marked) {
    nlohmann::json excluded = nlohmann::json::array(), by_episode = nlohmann::json::object();
    for (const auto& [id, m] : *marks) {
      if (m.excluded) excluded.push_back({{"episode", id.value()}, {"reason", m.exclusion_reason}});
      by_episode[std::to_string(id.value())] = {
          {"flagged", m.flagged}, {"tags", m.tags}, {"excluded", m.excluded}, {"reason", m.exclusion_reason}};
    }
    j["excluded"] = excluded;
    j["marks"] = by_episode;
  }
  // Only runs with model agents have a usage section, so built-in runs keep byte-identical reports.
  if (!usage.empty()) {
    j["usage"] = nlohmann::json::object();
    for (const auto& [agent, u] : usage) j["usage"][agent] = u.json();
  }
  return j;
}

std::string report_html(const nlohmann::json& r) {
  std::ostringstream h;
  const std::string run = escape_markup(r["run"].get<std::string>());
  h << "<!doctype html><html><head><meta charset=\"utf-8\"><title>ManiTaskGen-LCM report " << run
    << "</title><style>body{font-family:sans-serif;margin:24px;color:#222}table{border-collapse:collapse;margin:12px 0}"
       "th,td{border:1px solid #bbb;padding:4px 10px;text-align:right}th{background:#eee}td:first-child,th:first-child"
       "{text-align:left}h2{margin-top:28px}.note{color:#666;font-size:90%}.ci{color:#777}</style></head><body>";
  h << "<h1>Run " << run << "</h1>";
  h << "<p>" << r["episodes"].get<std::int64_t>() << " episodes, " << r["scored"].get<std::int64_t>() << " scored"
    << (r["errors"].get<std::int64_t>() ? ", " + std::to_string(r["errors"].get<std::int64_t>()) + " given up (infrastructure)" : "")
    << ". SR " << with_interval_html(r, "sr") << " %, IP " << with_interval_html(r, "ip") << ".</p>";
  if (r.contains("excluded") && !r["excluded"].empty()) {
    h << "<p class=note>" << r["excluded"].size() << " episode(s) excluded by a person, outside every figure:";
    for (const auto& e : r["excluded"]) {
      h << " " << e["episode"] << " (" << escape_markup(e["reason"].get<std::string>()) << ")";
    }
    h << ". Marks are kept in marks.sqlite with who made them; the results are unchanged.</p>";
  }
  // Table 3: rows = agents, columns = levels (IP, SR), the paper's average over Levels 1-3 and
  // the pooled figure; each with its 95 % interval beneath.
  std::vector<std::string> levels;
  for (const auto& [l, v] : r["by_level"].items()) levels.push_back(l);
  const std::string avg = paper_average_label(r);
  h << "<h2>Results by level</h2><table><tr><th rowspan=2>agent</th>";
  for (const auto& l : levels) h << "<th colspan=2>Level " << l << "</th>";
  if (!avg.empty()) h << "<th colspan=2>" << avg << "</th>";
  h << "<th colspan=2>All levels</th><th rowspan=2>episodes</th></tr><tr>";
  for (std::size_t i = 0; i < levels.size() + (avg.empty() ? 1 : 2); ++i) h << "<th>IP</th><th>SR (%)</th>";
  h << "</tr>";
  auto cells = [&h](const nlohmann::json& f) {
    h << "<td>" << with_interval_html(f, "ip") << "</td><td>" << with_interval_html(f, "sr") << "</td>";
  };
  for (const auto& [agent, a] : r["by_agent"].items()) {
    h << "<tr><td>" << escape_markup(agent) << "</td>";
    for (const auto& l : levels) {
      if (a.contains("by_level") && a["by_level"].contains(l)) {
        cells(a["by_level"][l]);
      } else {
        h << "<td></td><td></td>";
      }
    }
    if (!avg.empty()) {
      // An agent that lacks one of the run's levels has another average: left blank, not mislabelled.
      if (a.contains("paper_avg") && !a["paper_avg"].is_null() && average_label(a["paper_avg"]["levels"]) == avg) {
        cells(a["paper_avg"]);
      } else {
        h << "<td></td><td></td>";
      }
    }
    cells(a);
    h << "<td>" << a["episodes"] << "</td></tr>";
  }
  h << "</table><p class=note>IP: intermediate points (25 per milestone: source reached, item picked, "
       "destination reached, placed as asked; Level 3 averages its sub-tasks). SR: success rate. Beneath each "
       "figure its 95 % interval: Wilson's for SR, a seeded bootstrap of episodes for IP; "
    << avg << " is the mean of the levels' figures, as in the paper's Table 3 (docs/statistics.md).</p>";
  h << repeats_html(r);
  h << "<h2>Failure taxonomy</h2><table><tr><th>cause</th><th style=\"text-align:left\">meaning</th><th>episodes</th></tr>";
  std::vector<std::pair<std::string, std::int64_t>> causes;
  for (const auto& [cause, n] : r["causes"].items()) causes.emplace_back(cause, n.get<std::int64_t>());
  std::stable_sort(causes.begin(), causes.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  for (const auto& [cause, n] : causes) {
    const auto c = episode::cause_from_string(cause);
    h << "<tr><td>" << escape_markup(cause) << "</td><td style=\"text-align:left\">"
      << escape_markup(c ? episode::explain(*c) : "") << "</td><td>" << n << "</td></tr>";
  }
  h << "</table>";
  // Failures per agent: one column per cause, in the order above.
  if (!causes.empty()) {
    h << "<table><tr><th>agent</th>";
    for (const auto& [cause, n] : causes) h << "<th>" << escape_markup(cause) << "</th>";
    h << "</tr>";
    for (const auto& [agent, a] : r["by_agent"].items()) {
      h << "<tr><td>" << escape_markup(agent) << "</td>";
      for (const auto& [cause, n] : causes) {
        h << "<td>" << (a.contains("causes") && a["causes"].contains(cause) ? a["causes"][cause].get<std::int64_t>() : 0)
          << "</td>";
      }
      h << "</tr>";
    }
    h << "</table>";
  }
  // Stages in the order an episode passes them, not alphabetically.
  h << "<table><tr><th>stage reached</th><th style=\"text-align:left\">meaning</th><th>episodes</th></tr>";
  for (const episode::Stage stage : episode::kStagesInOrder) {
    const char* name = episode::to_string(stage);
    if (!r["stages"].contains(name)) continue;
    h << "<tr><td>" << name << "</td><td style=\"text-align:left\">" << episode::explain(stage) << "</td><td>"
      << r["stages"][name] << "</td></tr>";
  }
  h << "</table>";
  h << "<h2>Failure Sankey: task level &rarr; stage reached &rarr; cause &rarr; outcome</h2>";
  h << sankey_svg(r["sankey"], kSankeyWidth, kSankeyHeight);
  if (r.contains("usage")) {
    h << "<h2>Model usage</h2><table><tr><th>agent</th><th>calls</th><th>from cache</th><th>input tokens</th>"
         "<th>output tokens</th><th>images</th><th>list price ($)</th><th>spent ($)</th><th>mean latency (ms)</th>"
         "<th>prompts</th></tr>";
    for (const auto& [agent, u] : r["usage"].items()) {
      std::string versions;
      for (const auto& v : u["prompt_versions"]) versions += (versions.empty() ? "" : ", ") + v.get<std::string>();
      h << "<tr><td>" << escape_markup(agent) << "</td><td>" << u["calls"] << "</td><td>" << u["cache_hits"] << "</td><td>"
        << u["input_tokens"] << "</td><td>" << u["output_tokens"] << "</td><td>" << u["images"] << "</td><td>"
        << u["cost_usd"] << (u.value("price_known", true) ? "" : " (a guess)") << "</td><td>"
        << (u.value("price_known", true) ? u["spent_usd"].dump() : "&ndash;") << "</td><td>" << u["mean_latency_ms"] << "</td><td>"
        << escape_markup(versions) << "</td></tr>";
    }
    h << "</table><p class=note>List price: what the answers used would cost at the price table's rates (the "
         "same on a cached rerun). Spent: what this run paid (answers from the response cache cost nothing); "
         "an endpoint of your own has no price, so its list price is the table's guess and nothing is "
         "counted as spent.</p>";
  }
  // Built-in agents call no model: a line of zero tokens and $0 would only look like a missing figure.
  if (r.contains("usage")) {
    h << "<p class=note>tokens in " << r["tokens"]["input"] << ", out " << r["tokens"]["output"]
      << "; estimated cost $" << r["cost_usd"] << "</p>";
  }
  h << "</body></html>\n";
  return h.str();
}

void write_report_png(const nlohmann::json& report, const std::filesystem::path& file) {
  sankey_png(report["sankey"], "Run " + report["run"].get<std::string>() + ": SR " + fmt(report["sr"].get<double>()) +
                                    " %, IP " + fmt(report["ip"].get<double>()),
             file, 1400, 760);
}

nlohmann::json write_reports(const std::filesystem::path& run_dir, const std::string& html) {
  const auto rows = read_results(run_dir / "results.sqlite");
  const auto marks = current_marks(read_marks(run_dir));
  const nlohmann::json report = make_report(rows, run_dir.filename().string(), &marks);
  write_json_file(run_dir / "report.json", report);
  const std::filesystem::path html_file = html.empty() ? run_dir / "report.html" : std::filesystem::path(html);
  write_file_atomically(html_file, [&](std::ostream& out) { out << report_html(report); });
  write_report_png(report, run_dir / "report.png");
  return report;
}

}  // namespace mtg::orchestrator
