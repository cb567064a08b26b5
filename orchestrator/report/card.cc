#include "orchestrator/report/card.h"

#include <sstream>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "orchestrator/report/leaderboard.h"
#include "orchestrator/report/report.h"
#include "orchestrator/run/marks.h"
#include "orchestrator/run/provenance.h"
#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator {
namespace {

// The benchmark's paper as arXiv lists it (arXiv:2505.20726). The paper text kept in
// shared/reference is an earlier, anonymous submission under another title, so nothing here can
// check the authors' names: the card cites title and arXiv id and sends the reader there for
// them, rather than print names it cannot vouch for.
constexpr const char* kPaperTitle =
    "ManiTaskGen: A Comprehensive Task Generator for Benchmarking and Improving Vision-Language Agents on "
    "Embodied Decision-Making";
constexpr int kPaperYear = 2025;
constexpr const char* kPaperArxiv = "2505.20726";
constexpr const char* kToolName = "ManiTaskGen-LCM";

// A member of an object, or null: plans from before provenance lack every key.
nlohmann::json member(const nlohmann::json& j, const char* key) {
  return j.is_object() && j.contains(key) ? j[key] : nlohmann::json(nullptr);
}

std::string text_of(const nlohmann::json& v) {
  if (v.is_null()) return "unknown";
  return v.is_string() ? v.get<std::string>() : v.dump();
}

// Agent names and reasons are free text: a '|' would end a table cell.
std::string cell(const std::string& s) {
  std::string out;
  for (const char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string joined(const nlohmann::json& strings, const std::string& separator) {
  std::string out;
  for (const auto& s : strings) out += (out.empty() ? "" : separator) + text_of(s);
  return out;
}

nlohmann::json figures(const nlohmann::json& f) {
  nlohmann::json out;
  for (const char* key : {"episodes", "sr", "sr_ci", "ip", "ip_ci"}) {
    if (f.contains(key)) out[key] = f[key];
  }
  return out;
}

void results_markdown(std::ostringstream& o, const nlohmann::json& card) {
  o << "\n## Results\n\n";
  if (card["results"].empty()) {
    o << "No episode was scored.\n";
    return;
  }
  o << "| agent | levels | episodes | SR % [95 % CI] | IP [95 % CI] |\n|:---|:---|---:|---:|---:|\n";
  auto line = [&o](const std::string& agent, const std::string& levels, const nlohmann::json& f) {
    o << "| " << cell(agent) << " | " << levels << " | " << f.value("episodes", std::int64_t{0}) << " | "
      << with_interval(f, "sr") << " | " << with_interval(f, "ip") << " |\n";
  };
  for (const auto& [agent, a] : card["results"].items()) {
    for (const auto& [level, f] : a["by_level"].items()) line(agent, "L" + level, f);
    if (!a["paper_avg"].is_null()) {  // over the agent's own levels, as `mtg report` prints it
      nlohmann::json f = a["paper_avg"];
      std::int64_t n = 0;
      for (const auto& l : f["levels"]) n += a["by_level"][l.get<std::string>()]["episodes"].get<std::int64_t>();
      f["episodes"] = n;
      line(agent, average_label(f["levels"]), f);
    }
    line(agent, "all", a["all"]);
  }
  const std::string avg = card["average_label"].get<std::string>();
  o << "\nSR: success rate (%); IP: intermediate points. Each with its 95 % interval: Wilson's for SR, a seeded "
       "bootstrap of episodes for IP"
    << (avg.empty() ? "" : "; " + avg + " is the mean of the levels' figures, as in the paper's Table 3")
    << " (docs/statistics.md).\n";
}

void cost_markdown(std::ostringstream& o, const nlohmann::json& card) {
  o << "\n## Cost\n\n";
  if (card["cost"].empty()) {
    o << "No model agent: nothing was spent on model calls.\n";
    return;
  }
  o << "| agent | calls | from cache | input tokens | output tokens | images | list price ($) | spent ($) |\n"
       "|:---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& [agent, u] : card["cost"].items()) {
    const bool priced = u.value("price_known", true);
    o << "| " << cell(agent) << " | " << u["calls"] << " | " << u["cache_hits"] << " | " << u["input_tokens"] << " | "
      << u["output_tokens"] << " | " << u["images"] << " | " << u["cost_usd"] << (priced ? "" : " (a guess)") << " | "
      << (priced ? u["spent_usd"].dump() : "–") << " |\n";
  }
  o << "\nList price: the answers used at the price table's rates; spent: what this run paid (cached answers "
       "cost nothing). An endpoint of one's own has no price: its list price is a guess.\n";
}

void provenance_markdown(std::ostringstream& o, const nlohmann::json& card) {
  o << "\n## Provenance\n\n";
  const nlohmann::json& p = card["provenance"];
  if (p.is_null()) {
    o << "The run's plan predates provenance: where it came from is not recorded.\n";
    return;
  }
  o << "- mtg version: " << text_of(p["mtg_version"]) << "\n- git revision: " << text_of(p["git_revision"]) << "\n";
  o << "- command: `" << (p["command"].is_array() ? joined(p["command"], " ") : text_of(p["command"])) << "`\n";
  o << "- planned at: " << text_of(p["planned_at"]) << " on " << text_of(p["host"]) << "\n";
}

void excluded_markdown(std::ostringstream& o, const nlohmann::json& card) {
  o << "\n## Episodes excluded by a person\n\n";
  if (card["excluded"].empty()) {
    o << "None.\n";
    return;
  }
  o << card["excluded"].size() << " episode(s), outside every figure above (marks.sqlite keeps who and when):\n\n";
  for (const auto& e : card["excluded"]) o << "- episode " << e["episode"] << ": " << text_of(e["reason"]) << "\n";
}

void cite_markdown(std::ostringstream& o, const nlohmann::json& card) {
  const nlohmann::json& c = card["cite"];
  const nlohmann::json& paper = c["paper"];
  o << "\n## How to cite\n\n";
  o << "- The benchmark: *" << text_of(paper["title"]) << "* (" << paper["year"] << "), arXiv:" << text_of(paper["arxiv"])
    << " (" << text_of(paper["url"]) << "; authors as listed there).\n";
  o << "- The tool: " << text_of(c["tool"]["name"]) << " " << text_of(c["tool"]["version"]) << " (revision "
    << text_of(c["tool"]["revision"]) << ").\n";
  o << "- The suite: `" << text_of(c["suite"]["id"]) << "`.\n\n";
  // No author field: take it from the arXiv entry (see kPaperTitle).
  o << "```bibtex\n@misc{manitaskgen" << paper["year"] << ",\n  title = {" << text_of(paper["title"]) << "},\n  year = {"
    << paper["year"] << "},\n  eprint = {" << text_of(paper["arxiv"]) << "},\n  archivePrefix = {arXiv}\n}\n```\n";
}

}  // namespace

nlohmann::json card_of(const nlohmann::json& report, const nlohmann::json& plan) {
  const nlohmann::json provenance = member(plan, "provenance");
  nlohmann::json card;
  card["run"] = report["run"];
  const std::string suite = suite_identity(provenance);
  card["suite"] = {{"id", suite}, {"declared", member(provenance, "suite")}, {"task_set", task_set_identity(provenance)}};
  if (plan.is_object() && plan.contains("agents") && plan["agents"].is_array()) {
    card["agents"] = plan["agents"];
  } else {
    card["agents"] = nlohmann::json::array();
    for (const auto& [agent, a] : report["by_agent"].items()) card["agents"].push_back(agent);
  }
  card["model_settings"] = member(provenance, "model_settings");
  for (const char* key : {"episodes", "scored", "errors"}) card[key] = report[key];
  card["average_label"] = paper_average_label(report);
  card["results"] = nlohmann::json::object();
  for (const auto& [agent, a] : report["by_agent"].items()) {
    card["results"][agent] = {{"by_level", a["by_level"]}, {"paper_avg", member(a, "paper_avg")}, {"all", figures(a)}};
  }
  // The report has usage only for agents that called a model: human and replay agents cost nothing.
  card["cost"] = report.contains("usage") ? report["usage"] : nlohmann::json::object();
  if (provenance.is_object()) {
    card["provenance"] = nlohmann::json::object();
    for (const char* key : {"mtg_version", "git_revision", "command", "planned_at", "host"}) {
      card["provenance"][key] = member(provenance, key);
    }
  } else {
    card["provenance"] = nullptr;
  }
  card["excluded"] = report.contains("excluded") ? report["excluded"] : nlohmann::json::array();
  card["cite"] = {{"paper",
                   {{"title", kPaperTitle},
                    {"year", kPaperYear},
                    {"arxiv", kPaperArxiv},
                    {"url", std::string("https://arxiv.org/abs/") + kPaperArxiv}}},
                  {"tool",
                   {{"name", kToolName},
                    {"version", member(provenance, "mtg_version")},
                    {"revision", member(provenance, "git_revision")}}},
                  {"suite", {{"id", suite}}}};
  return card;
}

nlohmann::json make_card(const std::filesystem::path& run_dir) {
  if (!std::filesystem::exists(run_dir / "results.sqlite")) {
    throw Error(run_dir.string() + ": not a run folder (no results.sqlite)");
  }
  std::filesystem::path named = std::filesystem::absolute(run_dir).lexically_normal();
  if (!named.has_filename()) named = named.parent_path();  // "runs/a/"
  // As write_reports makes it: the card quotes the figures report.json holds.
  const auto marks = current_marks(read_marks(run_dir));
  const nlohmann::json report = make_report(read_results(run_dir / "results.sqlite"), named.filename().string(), &marks);
  const nlohmann::json plan = std::filesystem::exists(run_dir / "plan.json") ? read_json_file(run_dir / "plan.json")
                                                                             : nlohmann::json::object();
  return card_of(report, plan);
}

std::string card_markdown(const nlohmann::json& card) {
  std::ostringstream o;
  o << "# Result card: " << text_of(card["run"]) << "\n\n";
  const nlohmann::json& suite = card["suite"];
  o << "- Suite: `" << text_of(suite["id"]) << "`";
  // Not the suite file's path: a card is for others to read, and where the run lived stays private.
  for (const char* key : {"name", "digest"}) {
    if (suite["declared"].is_object() && suite["declared"].contains(key)) o << "; " << key << " " << text_of(suite["declared"][key]);
  }
  o << "\n";
  if (!suite["task_set"].get<std::string>().empty() && suite["declared"].is_object()) {
    o << "- Task set: " << suite["task_set"].get<std::string>() << "\n";
  }
  o << "- Agents: " << cell(joined(card["agents"], ", ")) << "\n";
  o << "- Episodes: " << card["scored"] << " scored of " << card["episodes"];
  if (card["errors"].get<std::int64_t>() > 0) {
    o << " (" << card["errors"] << " given up by the infrastructure, outside SR and IP)";
  }
  o << "\n\n## Model settings\n\n";
  if (card["model_settings"].is_object() && !card["model_settings"].empty()) {
    for (const auto& [key, value] : card["model_settings"].items()) o << "- " << key << ": " << text_of(value) << "\n";
  } else {
    o << "None: no model agent ran.\n";
  }
  results_markdown(o, card);
  cost_markdown(o, card);
  provenance_markdown(o, card);
  excluded_markdown(o, card);
  cite_markdown(o, card);
  return o.str();
}

void write_card(const std::filesystem::path& run_dir) {
  const nlohmann::json card = make_card(run_dir);
  // Renamed over the targets: a link at card.md is replaced, never written through.
  write_file_atomically(run_dir / "card.json", [&](std::ostream& out) { out << card.dump(1, ' ') << '\n'; });
  write_file_atomically(run_dir / "card.md", [&](std::ostream& out) { out << card_markdown(card); });
}

}  // namespace mtg::orchestrator
