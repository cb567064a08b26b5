#include "core/tasks/feasibility.h"

#include <fstream>

#include "core/util/error.h"

namespace mtg::tasks {

std::vector<Vote> load_votes(const std::string& jsonl_file) {
  std::ifstream in(jsonl_file);
  if (!in) throw Error(jsonl_file + ": cannot open votes file");
  std::vector<Vote> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = jsonl_file + ":" + std::to_string(n);
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception&) {
      throw Error(where + ": not a JSON object");
    }
    for (const char* key : {"task_id", "voter", "verdict"}) {
      if (!j.contains(key) || !j[key].is_string()) throw Error(where + ": missing string field '" + key + "'");
    }
    Vote v{j["task_id"], j["voter"], j["verdict"]};
    if (v.verdict != kFeasible && v.verdict != kPartiallyFeasible && v.verdict != kNotFeasible) {
      throw Error(where + ": unknown verdict '" + v.verdict + "' (Feasible, Partially feasible, Not feasible)");
    }
    out.push_back(std::move(v));
  }
  return out;
}

std::map<std::string, std::vector<Vote>> group_votes(const std::vector<Vote>& votes) {
  std::map<std::string, std::vector<Vote>> out;
  for (const Vote& v : votes) out[v.task_id].push_back(v);
  return out;
}

bool accepted(const std::vector<Vote>& votes) {
  std::size_t yes = 0;
  for (const Vote& v : votes) yes += v.verdict == kFeasible ? 1 : 0;
  return 2 * yes > votes.size();
}

}  // namespace mtg::tasks
