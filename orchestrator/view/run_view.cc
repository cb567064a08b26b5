#include "orchestrator/view/run_view.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <map>
#include <set>

#include "agents/vlm/model_spec.h"
#include "core/episode/outcomes.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "orchestrator/report/paper_table3.h"
#include "orchestrator/report/report.h"
#include "orchestrator/run/provenance.h"
#include "orchestrator/run/run_lock.h"

namespace mtg::orchestrator::view {

namespace fs = std::filesystem;
using nlohmann::json;

json row_json(const EpisodeRow& r) {
  return {{"episode_id", r.episode_id.value()},
          {"task_id", r.task_id},
          {"scene", r.scene},
          {"level", r.level},
          {"task_type", r.task_type},
          {"agent", r.agent},
          {"attempt", r.attempt},
          {"status", r.status},
          {"success", r.success},
          {"ip", r.ip},
          {"stage", r.stage},
          {"stage_text", episode::explain_stage(r.stage)},
          {"cause", r.cause},
          {"cause_text", r.success ? std::string_view() : episode::explain_cause(r.cause)},
          {"steps", r.steps},
          {"invalid_actions", r.invalid_actions},
          {"input_tokens", r.usage.input_tokens},
          {"output_tokens", r.usage.output_tokens},
          {"cost_usd", r.usage.cost_usd},
          {"model_calls", r.usage.model_calls},
          {"prompt_version", r.usage.prompt_version},
          {"worker", r.worker},
          {"detail", r.detail}};
}

namespace {

// With repeats (`--repeat`), the task × agent grid: each cell is [successes, scored episodes] of
// one agent on one task. Null when no task ran more than once for an agent: the list says it all.
json repeats_grid(const std::vector<EpisodeRow>& rows) {
  std::map<std::string, std::pair<int, std::map<std::string, std::pair<int, int>>>> tasks;  // task -> level, agent -> (c, n)
  std::set<std::string> agents;
  bool repeated = false;
  for (const EpisodeRow& r : rows) {
    if (r.status != "scored") continue;
    auto& [level, cells] = tasks[r.task_id];
    level = r.level;
    auto& [c, n] = cells[r.agent];
    c += r.success ? 1 : 0;
    ++n;
    repeated = repeated || n > 1;
    agents.insert(r.agent);
  }
  if (!repeated) return nullptr;
  json out = {{"agents", agents}, {"rows", json::array()}};
  for (const auto& [task, entry] : tasks) {
    json cells = json::array();
    for (const std::string& agent : agents) {
      const auto it = entry.second.find(agent);
      cells.push_back(it == entry.second.end() ? json(nullptr) : json::array({it->second.first, it->second.second}));
    }
    out["rows"].push_back({{"task", task}, {"level", entry.first}, {"cells", cells}});
  }
  return out;
}

}  // namespace

RunView::RunView(std::string name, fs::path dir) : name_(std::move(name)), dir_(std::move(dir)), index_(dir_) {
  const fs::path plan_file = dir_ / "plan.json";
  std::ifstream in(plan_file);
  if (!in) throw Error(dir_.string() + ": not a run folder (no plan.json)");
  const json plan = json::parse(in, nullptr, false);
  if (plan.is_discarded() || !plan.is_object()) throw Error(plan_file.string() + ": not valid JSON");
  planned_ = plan.value("episodes", json::array()).size();
  per_repeat_ = static_cast<std::int64_t>(planned_) / std::max(1, plan.value("repeat", 1));
  tasks_db_ = plan.value("tasks_db", "");
  plan_summary_ = {{"run_id", plan.value("run_id", "")},
                   {"agents", plan.value("agents", json::array())},
                   {"levels", plan.value("levels", json::array())},
                   {"render", plan.value("render", false)},
                   // What made the run (orchestrator/run/provenance.h): null for runs from before it.
                   {"provenance", plan.value("provenance", json())},
                   {"settings", {{"tasks_db", tasks_db_},
                                 {"scenes", plan.value("scenes", json::array())},
                                 {"limit", plan.value("limit", 0)},
                                 {"repeat", plan.value("repeat", 1)},
                                 {"seed", plan.value("seed", std::uint64_t{0})},
                                 {"step_limit", plan.value("step_limit", 0)},
                                 {"image_size", std::to_string(plan.value("image_width", 0)) + "x" +
                                                    std::to_string(plan.value("image_height", 0))},
                                 {"object_names", plan.value("object_names", false)},
                                 {"lookalike_aid", plan.value("lookalike_aid", std::string("both"))},
                                 {"parallel", plan.value("parallel", 0)},
                                 {"remote", plan.value("remote", false)}}}};
  indexer_ = std::thread([this] {
    while (!stop_) {
      try {
        index_.refresh();
      } catch (const std::exception& e) {
        log::warn(name_ + ": " + e.what());
      }
      for (int i = 0; i < 10 && !stop_; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
}

RunView::~RunView() {
  stop_ = true;
  if (indexer_.joinable()) indexer_.join();
}

RunView::Rows RunView::rows() {
  const fs::path db = dir_ / "results.sqlite";
  std::string stamp;
  for (const fs::path& f : {db, fs::path(db.string() + "-wal")}) {
    std::error_code ec;
    const auto size = fs::file_size(f, ec);
    if (ec) continue;
    stamp += std::to_string(size) + ":" + std::to_string(fs::last_write_time(f, ec).time_since_epoch().count()) + ";";
  }
  const std::lock_guard lock(rows_mutex_);
  if (stamp != rows_stamp_) {
    auto fresh = fs::exists(db) ? read_results(db) : std::vector<EpisodeRow>{};
    std::sort(fresh.begin(), fresh.end(),
              [](const EpisodeRow& a, const EpisodeRow& b) { return a.episode_id < b.episode_id; });
    rows_ = std::make_shared<const std::vector<EpisodeRow>>(std::move(fresh));
    rows_stamp_ = stamp;
  }
  return rows_;
}

json RunView::summary() {
  const Rows all = rows();
  const std::size_t finished = all->size();
  json s = plan_summary_;
  // The run list's figures (issue 52): SR and IP over the scored episodes a person did not
  // exclude, as the overview counts them; null before the first.
  const auto marked = current_marks(read_marks(dir_));
  std::int64_t scored = 0, successes = 0;
  double ip = 0.0;
  for (const EpisodeRow& r : without_excluded(*all, marked)) {
    if (r.status != "scored") continue;
    ++scored;
    successes += r.success ? 1 : 0;
    ip += r.ip;
  }
  s["scored"] = scored;
  s["sr"] = scored > 0 ? json(100.0 * static_cast<double>(successes) / static_cast<double>(scored)) : json(nullptr);
  s["ip"] = scored > 0 ? json(ip / static_cast<double>(scored)) : json(nullptr);
  const json& provenance = plan_summary_.value("provenance", json::object());
  s["suite"] = provenance.is_object() && provenance.contains("suite") ? provenance["suite"].value("id", std::string())
                                                                      : std::string();
  s["name"] = name_;
  s["dir"] = fs::absolute(dir_).string();
  s["planned"] = planned_;
  s["finished"] = finished;
  s["live"] = finished < planned_;
  s["damage"] = index_.damage(!run_in_progress(dir_));
  s["sessions"] = read_sessions(dir_);
  return s;
}

json RunView::marks(bus::EpisodeId episode) const {
  const std::vector<MarkEntry> trail = read_marks(dir_);
  json by_episode = json::object(), entries = json::array();
  for (const auto& [id, m] : current_marks(trail)) {
    if (episode.valid() && id != episode) continue;
    by_episode[std::to_string(id.value())] = {
        {"flagged", m.flagged}, {"tags", m.tags}, {"excluded", m.excluded}, {"reason", m.exclusion_reason}};
  }
  for (const MarkEntry& e : trail) {
    if (episode.valid() && e.episode != episode) continue;
    entries.push_back({{"episode", e.episode.value()}, {"action", to_string(e.action)}, {"tag", e.tag},
                       {"reason", e.reason}, {"who", e.who}, {"at", e.at}});
  }
  return {{"marks", by_episode}, {"trail", entries}};
}

void RunView::add_mark(const MarkEntry& entry) {
  const Rows all = rows();
  if (std::none_of(all->begin(), all->end(), [&](const EpisodeRow& r) { return r.episode_id == entry.episode; })) {
    throw Error("run " + name_ + " has no episode " + to_string(entry.episode));
  }
  orchestrator::add_mark(dir_, entry);
}

RunRows RunView::compare_rows() {
  return run_rows(name_, *rows(), current_marks(read_marks(dir_)), task_set_identity(plan_summary_["provenance"]),
                  per_repeat_);
}

std::vector<std::string> RunView::damage_read_through() {
  index_.refresh();
  return index_.damage(!run_in_progress(dir_));
}

LeaderboardRun RunView::leaderboard_run() {
  return {name_, without_excluded(*rows(), current_marks(read_marks(dir_))),
          suite_identity(plan_summary_.value("provenance", json(nullptr))), per_repeat_};
}

json RunView::overview() {
  const Rows all = rows();
  const std::int64_t stamp = marks_version(dir_);  // this viewer's marks or another's
  {
    // The report is recomputed only when the results or the marks changed (a live page asks
    // every 2 s).
    const std::lock_guard lock(rows_mutex_);
    if (overview_rows_ == all && overview_marks_ == stamp) {
      json o = overview_;
      o["damage"] = index_.damage(!run_in_progress(dir_));  // found by the indexer meanwhile
      return o;
    }
  }
  json o = summary();
  const auto marked = current_marks(read_marks(dir_));
  o["report"] = make_report(*all, plan_summary_["run_id"].get<std::string>(), &marked);
  o["paper"] = paper_table3();
  std::set<std::string> prompt_versions;
  std::set<std::string> workers;  // the hosts that ran episodes of a multi-host run
  bool model_agents = false;
  for (const EpisodeRow& r : *all) {
    if (!r.usage.prompt_version.empty()) prompt_versions.insert(r.usage.prompt_version);
    if (!r.worker.empty()) workers.insert(r.worker);
    model_agents = model_agents || (r.usage.model_calls > 0 && vlm::is_model_spec(r.agent));
  }
  o["prompt_versions"] = prompt_versions;
  o["workers"] = workers;
  o["grid"] = repeats_grid(without_excluded(*all, marked));
  o["model_agents"] = model_agents;
  const std::lock_guard lock(rows_mutex_);
  overview_rows_ = all;
  overview_marks_ = stamp;
  overview_ = o;
  return o;
}

json RunView::agent_report(const std::string& agent) {
  const Rows all = rows();
  std::vector<EpisodeRow> mine;
  for (const EpisodeRow& r : *all) {
    if (r.agent == agent) mine.push_back(r);
  }
  if (mine.empty()) return nullptr;
  const auto marked = current_marks(read_marks(dir_));
  return make_report(mine, plan_summary_["run_id"].get<std::string>(), &marked);
}

const TaskTexts& RunView::task_texts() {
  std::call_once(texts_once_, [this] {
    // A run looked at on another machine may not have its task set: then ids only.
    std::error_code ec;
    if (tasks_db_.empty() || !fs::exists(tasks_db_, ec)) return;
    try {
      for (const tasks::Task& t : tasks::read_tasks(tasks_db_)) texts_.emplace(t.id, t.text);
    } catch (const std::exception& e) {
      log::warn(name_ + ": task texts not shown (" + e.what() + ")");
    }
  });
  return texts_;
}

json RunView::episodes(const EpisodeQuery& query, std::size_t offset, std::size_t limit) {
  const Rows all = rows();
  const auto marked = current_marks(read_marks(dir_));
  const TaskTexts& texts = task_texts();
  if (query.text) index_.refresh();  // replies are searched: the recording read to its end first
  const std::vector<std::size_t> selected = select_episodes(*all, texts, query, said_search());
  json list = json::array();
  for (std::size_t k = offset; k < selected.size() && list.size() < limit; ++k) {
    const EpisodeRow& r = (*all)[selected[k]];
    json row = row_json(r);
    const auto text = texts.find(r.task_id);
    row["task_text"] = text == texts.end() ? "" : text->second;
    // Episodes are laid out repeat by repeat (run_plan.h): the k-th block of tasks x agents.
    row["repeat"] = per_repeat_ > 0 ? r.episode_id.value() / per_repeat_ : 0;
    if (const auto m = marked.find(r.episode_id); m != marked.end()) {
      row["marks"] = {{"flagged", m->second.flagged}, {"tags", m->second.tags}, {"excluded", m->second.excluded}};
    }
    list.push_back(std::move(row));
  }
  return {{"total", selected.size()}, {"offset", offset}, {"rows", list}};
}

json RunView::neighbours(const EpisodeQuery& query, bus::EpisodeId id) {
  const Rows all = rows();
  if (query.text) index_.refresh();
  const std::vector<std::size_t> selected = select_episodes(*all, task_texts(), query, said_search());
  const auto at = std::find_if(selected.begin(), selected.end(), [&](std::size_t i) { return (*all)[i].episode_id == id; });
  if (at == selected.end()) return {{"position", nullptr}, {"total", selected.size()}, {"previous", nullptr}, {"next", nullptr}};
  const auto k = static_cast<std::size_t>(at - selected.begin());
  const auto id_at = [&](std::size_t i) { return json((*all)[selected[i]].episode_id.value()); };
  return {{"position", k},
          {"total", selected.size()},
          {"previous", k > 0 ? id_at(k - 1) : json(nullptr)},
          {"next", k + 1 < selected.size() ? id_at(k + 1) : json(nullptr)}};
}

std::vector<RecordedMessage> RunView::messages_of(bus::EpisodeId id) {
  auto messages = index_.messages_of(id);
  if (messages.empty()) {  // not indexed yet (a live run, or the first scan still going)
    index_.refresh();
    messages = index_.messages_of(id);
  }
  return messages;
}

json RunView::episode(bus::EpisodeId id, int attempt) {
  json row = nullptr;
  const Rows all = rows();
  const auto it = std::lower_bound(all->begin(), all->end(), id,
                                   [](const EpisodeRow& r, bus::EpisodeId v) { return r.episode_id < v; });
  if (it != all->end() && it->episode_id == id) row = row_json(*it);
  const auto messages = messages_of(id);
  if (row.is_null() && messages.empty()) return nullptr;
  if (attempt < 0 && !row.is_null()) attempt = row["attempt"].get<int>();
  json out = episode_trace(id, messages, attempt);
  out["row"] = row;
  out["run"] = name_;
  // A stored episode the recording shows nothing of: say why rather than show zero steps.
  if (out["steps"].empty() && !row.is_null()) {
    const bool given_up = row["status"] != "scored";
    out["missing"] = std::string(given_up ? "The infrastructure gave this episode up (" + row["detail"].get<std::string>() +
                                                "). "
                                          : "") +
                     "The recording holds no step of attempt " + out["attempt"].dump() + " (" +
                     (messages.empty() ? "no message of this episode at all" : "only other attempts' messages") +
                     "): " +
                     (index_.damage(!run_in_progress(dir_)).empty()
                          ? "the recording of its invocation may be missing from the folder."
                          : "they were lost where the recording is damaged; see the run's overview.");
  }
  return out;
}

json RunView::truth(bus::EpisodeId id, int attempt) {
  // Read when asked: a run that is still being made writes its key when it starts.
  return episode_truth(messages_of(id), attempt, bus::RecordedTruths(dir_));
}

std::optional<RecordedImage> RunView::image(bus::EpisodeId id, int attempt, int step, int index) {
  return observation_image(messages_of(id), attempt, step, index);
}

std::vector<std::string> run_names(const std::vector<std::filesystem::path>& dirs) {
  std::map<std::string, int> seen;
  std::vector<std::string> out;
  for (const auto& dir : dirs) {
    std::string name = std::filesystem::absolute(dir).lexically_normal().filename().string();
    if (name.empty()) name = std::filesystem::absolute(dir).lexically_normal().parent_path().filename().string();
    if (const int n = ++seen[name]; n > 1) name += "-" + std::to_string(n);
    out.push_back(std::move(name));
  }
  return out;
}

std::map<std::pair<int, int>, RecordedImage> RunView::images(bus::EpisodeId id, int attempt) {
  return observation_images(messages_of(id), attempt);
}

}  // namespace mtg::orchestrator::view
