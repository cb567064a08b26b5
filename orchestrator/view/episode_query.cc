#include "orchestrator/view/episode_query.h"

#include <algorithm>
#include <cctype>
#include <functional>

#include "core/util/error.h"

namespace mtg::orchestrator::view {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

const std::string& text_of(const TaskTexts& texts, const std::string& task) {
  static const std::string kNone;
  const auto it = texts.find(task);
  return it == texts.end() ? kNone : it->second;
}

// -1, 0, 1 as a is before, level with, after b in the column.
using Compare = std::function<int(const EpisodeRow&, const EpisodeRow&)>;

template <class T>
int three_way(const T& a, const T& b) {
  return a < b ? -1 : (b < a ? 1 : 0);
}

Compare compare_by(const std::string& field, const TaskTexts& texts) {
  if (field == "episode") return [](const auto& a, const auto& b) { return three_way(a.episode_id, b.episode_id); };
  if (field == "agent") return [](const auto& a, const auto& b) { return three_way(a.agent, b.agent); };
  if (field == "level") return [](const auto& a, const auto& b) { return three_way(a.level, b.level); };
  if (field == "scene") return [](const auto& a, const auto& b) { return three_way(a.scene, b.scene); };
  if (field == "task") return [](const auto& a, const auto& b) { return three_way(a.task_id, b.task_id); };
  if (field == "text") {
    return [&texts](const auto& a, const auto& b) { return three_way(text_of(texts, a.task_id), text_of(texts, b.task_id)); };
  }
  if (field == "verdict") {
    // Errors, failures, successes.
    const auto rank = [](const EpisodeRow& r) { return r.status != "scored" ? 0 : (r.success ? 2 : 1); };
    return [rank](const auto& a, const auto& b) { return three_way(rank(a), rank(b)); };
  }
  if (field == "ip") return [](const auto& a, const auto& b) { return three_way(a.ip, b.ip); };
  if (field == "stage") return [](const auto& a, const auto& b) { return three_way(a.stage, b.stage); };
  if (field == "cause") return [](const auto& a, const auto& b) { return three_way(a.cause, b.cause); };
  if (field == "steps") return [](const auto& a, const auto& b) { return three_way(a.steps, b.steps); };
  std::string all;
  for (const auto& f : sort_fields()) all += (all.empty() ? "" : ", ") + f;
  throw Error("query parameter 'sort' must be one of " + all + ", not " + field);
}

}  // namespace

bool EpisodeFilter::matches(const EpisodeRow& r) const {
  if (agent && r.agent != *agent) return false;
  if (scene && r.scene != *scene) return false;
  if (task && r.task_id != *task) return false;
  if (stage && r.stage != *stage) return false;
  if (status && r.status != *status) return false;
  if (level && r.level != *level) return false;
  if (success && r.success != *success) return false;
  if (cause) {
    // "success" names the successes' band of the Sankey, where the cause column is empty.
    const std::string wanted = *cause == "success" ? "" : *cause;
    if (r.cause != wanted || (*cause == "success") != r.success) return false;
  }
  return true;
}

const std::vector<std::string>& sort_fields() {
  static const std::vector<std::string> kFields = {"episode", "agent", "level", "scene", "task", "text",
                                                   "verdict", "ip",    "stage", "cause", "steps"};
  return kFields;
}

std::vector<std::size_t> select_episodes(const std::vector<EpisodeRow>& rows, const TaskTexts& texts,
                                         const EpisodeQuery& query, const SaidSearch& said) {
  const Compare compare = compare_by(query.sort, texts);
  const std::string needle = query.text ? lower(*query.text) : "";
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const EpisodeRow& r = rows[i];
    if (!query.filter.matches(r)) continue;
    if (!needle.empty() && lower(r.task_id).find(needle) == std::string::npos &&
        lower(text_of(texts, r.task_id)).find(needle) == std::string::npos && !(said && said(r.episode_id, needle))) {
      continue;
    }
    out.push_back(i);
  }
  std::stable_sort(out.begin(), out.end(), [&](std::size_t a, std::size_t b) {
    const int c = compare(rows[a], rows[b]);
    if (c != 0) return query.descending ? c > 0 : c < 0;
    return rows[a].episode_id < rows[b].episode_id;
  });
  return out;
}

}  // namespace mtg::orchestrator::view
