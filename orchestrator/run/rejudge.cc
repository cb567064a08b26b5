#include "orchestrator/run/rejudge.h"

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <map>

#include "bus/convert.h"
#include "core/episode/judge.h"
#include "core/util/error.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "orchestrator/run/run_plan.h"
#include "services/common/scene_cache.h"

namespace mtg::orchestrator {
namespace {

namespace fs = std::filesystem;

struct Recorded {
  std::map<int, mtg::episode_start_t> starts;                   // attempt -> start
  std::map<int, std::map<int, mtg::agent_action_t>> actions;     // attempt -> step -> answer
};

std::map<std::int64_t, Recorded> read_recording(const fs::path& run_dir, const std::string& run_id) {
  std::vector<fs::path> logs;
  for (const auto& entry : fs::directory_iterator(run_dir)) {
    if (entry.path().extension() == ".lcmlog") logs.push_back(entry.path());
  }
  std::sort(logs.begin(), logs.end());
  if (logs.empty()) throw Error(run_dir.string() + ": no recording (*.lcmlog)");
  std::map<std::int64_t, Recorded> out;
  for (const auto& log : logs) {
    lcm::LogFile file(log.string(), "r");
    if (!file.good()) throw Error(log.string() + ": cannot read recording");
    for (const lcm::LogEvent* ev = file.readNextEvent(); ev != nullptr; ev = file.readNextEvent()) {
      if (ev->channel == "MTG_EPISODE_START") {
        mtg::episode_start_t m{};
        if (m.decode(ev->data, 0, ev->datalen) < 0 || m.header.run_id != run_id) continue;
        out[m.header.episode_id].starts[m.header.attempt] = m;
      } else if (ev->channel.rfind("MTG_ACT_E", 0) == 0) {
        mtg::agent_action_t m{};
        if (m.decode(ev->data, 0, ev->datalen) < 0 || m.header.run_id != run_id) continue;
        out[m.header.episode_id].actions[m.header.attempt].emplace(m.step, m);  // first answer per step wins
      }
    }
  }
  return out;
}

}  // namespace

RejudgeReport rejudge_run(const fs::path& run_dir) {
  const RunPlan plan = load_plan(run_dir);
  const std::vector<EpisodeRow> recorded_rows = read_results(run_dir / "results.sqlite");
  const auto recording = read_recording(run_dir, plan.run_id);
  services::SceneCache scenes(plan.profile);
  RejudgeReport report;
  for (const EpisodeRow& original : recorded_rows) {
    EpisodeRow row = original;
    if (original.status == "scored") {
      const auto rec = recording.find(original.episode_id);
      if (rec == recording.end() || rec->second.starts.count(original.attempt) == 0) {
        throw Error(run_dir.string() + ": the recording lacks the start of episode " +
                    std::to_string(original.episode_id) + " attempt " + std::to_string(original.attempt));
      }
      const mtg::episode_start_t& start = rec->second.starts.at(original.attempt);
      const tasks::Task task = bus::from_message(start.task);
      const graph::SceneGraph& g = scenes.get(task.scene, start.data_dir);
      const episode::TaskGoal goal = episode::task_goal_from_json(g, task.goal);
      episode::EpisodeJudge judge(g, goal, task.level);
      episode::WorldState state = episode::initial_state(g);
      episode::RuleOptions rules;
      rules.step_limit = start.step_limit;
      const episode::TaskConstraints constraints{goal.protected_objects()};
      judge.observe(episode::StateUpdate{});
      const auto answers = rec->second.actions.find(original.attempt);
      for (int step = 0; !judge.done(); ++step) {
        if (answers == rec->second.actions.end() || answers->second.count(step) == 0) {
          throw Error(run_dir.string() + ": the recording lacks episode " + std::to_string(original.episode_id) +
                      "'s answer to step " + std::to_string(step));
        }
        const mtg::agent_action_t& a = answers->second.at(step);
        const episode::AgentAnswer answer{a.parsed_key, a.format_ok != 0, !a.error.empty()};
        judge.observe(episode::step_episode(g, state, answer, constraints, rules).update);
      }
      const episode::Verdict v = judge.verdict();
      row.success = v.success;
      row.ip = v.ip;
      row.stage = v.stage;
      row.cause = v.cause;
      row.steps = v.steps;
      row.invalid_actions = v.invalid_actions;
      row.subtask_ip = nlohmann::json(v.part_ip).dump();
      row.detail = v.detail;
    }
    if (verdict_fingerprint(row) == verdict_fingerprint(original)) {
      ++report.identical;
    } else {
      report.differences.push_back("episode " + std::to_string(row.episode_id) + " (" + row.task_id + "): recorded " +
                                   (original.success ? "success" : original.cause) + " IP " +
                                   std::to_string(original.ip) + ", now " + (row.success ? "success" : row.cause) +
                                   " IP " + std::to_string(row.ip));
    }
    report.rows.push_back(std::move(row));
  }
  return report;
}

}  // namespace mtg::orchestrator
