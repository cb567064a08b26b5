#include "orchestrator/run/rejudge.h"

#include <lcm/lcm-cpp.hpp>

#include <map>

#include "bus/channels.h"
#include "bus/convert.h"
#include "bus/recording.h"
#include "bus/truth_seal.h"
#include "core/episode/judge.h"
#include "core/graph/scene_cache.h"
#include "core/util/error.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"
#include "orchestrator/run/run_plan.h"

namespace mtg::orchestrator {
namespace {

namespace fs = std::filesystem;

struct Recorded {
  std::map<int, mtg::episode_start_t> starts;                   // attempt -> start
  std::map<int, mtg::episode_truth_t> truths;                   // attempt -> goal and plan
  std::map<int, std::map<int, mtg::agent_action_t>> actions;     // attempt -> step -> answer
};

std::map<bus::EpisodeId, Recorded> read_recording(const fs::path& run_dir, const std::string& run_id,
                                                  std::vector<bus::RecordingDamage>& damage) {
  std::map<bus::EpisodeId, Recorded> out;
  const bus::RecordedTruths answers(run_dir);
  const auto damaged = bus::for_each_recorded_event(run_dir, [&](const lcm::LogEvent& ev) {
    if (ev.channel == bus::kEpisodeStart) {
      mtg::episode_start_t m{};
      if (m.decode(ev.data, 0, ev.datalen) < 0 || m.header.run_id != run_id) return;
      out[bus::episode_of(m.header)].starts[m.header.attempt] = m;
    } else if (ev.channel == bus::kEpisodeTruth) {
      mtg::episode_truth_t m{};
      if (m.decode(ev.data, 0, ev.datalen) < 0 || m.header.run_id != run_id) return;
      out[bus::episode_of(m.header)].truths[m.header.attempt] = answers.open(m);
    } else if (bus::is_episode_channel(ev.channel, bus::EpisodeStream::kAction)) {
      mtg::agent_action_t m{};
      if (m.decode(ev.data, 0, ev.datalen) < 0 || m.header.run_id != run_id) return;
      out[bus::episode_of(m.header)].actions[m.header.attempt].emplace(m.step, m);  // first answer per step wins
    }
  });
  damage = damaged;
  return out;
}

// Why the recording may lack something of `episode`: the damage found in it that may explain it.
std::string because_of(const std::vector<bus::RecordingDamage>& damage, bus::EpisodeId episode) {
  const std::string why = bus::damage_for(damage, episode);
  return why.empty() ? "" : " (the recording is damaged: " + why + ")";
}

}  // namespace

RejudgeReport rejudge_run(const fs::path& run_dir) {
  const RunPlan plan = load_plan(run_dir);
  const std::vector<EpisodeRow> recorded_rows = read_results(run_dir / "results.sqlite");
  RejudgeReport report;
  std::vector<bus::RecordingDamage> damage;
  const auto recording = read_recording(run_dir, plan.run_id, damage);
  for (const bus::RecordingDamage& d : damage) report.damage.push_back(bus::describe(d));
  graph::SceneCache scenes(plan.profile, plan.platform_rules);
  for (const EpisodeRow& original : recorded_rows) {
    EpisodeRow row = original;
    if (original.status == "scored") {
      const auto rec = recording.find(original.episode_id);
      if (rec == recording.end() || rec->second.starts.count(original.attempt) == 0 ||
          rec->second.truths.count(original.attempt) == 0) {
        report.unjudged.push_back("the recording lacks the start of episode " + to_string(original.episode_id) +
                                  " attempt " + std::to_string(original.attempt) + because_of(damage, original.episode_id));
        continue;
      }
      const mtg::episode_start_t& start = rec->second.starts.at(original.attempt);
      const bus::EpisodeTask task = bus::from_messages(start.task, rec->second.truths.at(original.attempt));
      const graph::SceneGraph& g = scenes.get(task.scene, start.data_dir);
      const episode::TaskGoal goal = episode::task_goal_from_json(g, task.goal);
      episode::EpisodeJudge judge(g, goal, task.level);
      const episode::RuleOptions rules = bus::episode_rules(start);
      episode::WorldState state = episode::initial_state(g, rules.numbering);
      const episode::TaskConstraints constraints{goal.protected_objects()};
      judge.observe(episode::StateUpdate{});
      const auto answers = rec->second.actions.find(original.attempt);
      bool whole = true;
      for (int step = 0; !judge.done(); ++step) {
        if (answers == rec->second.actions.end() || answers->second.count(step) == 0) {
          report.unjudged.push_back("the recording lacks episode " + to_string(original.episode_id) +
                                    "'s answer to step " + std::to_string(step) + because_of(damage, original.episode_id));
          whole = false;
          break;
        }
        const episode::AgentAnswer answer = bus::to_answer(answers->second.at(step));
        judge.observe(episode::step_episode(g, state, answer, constraints, rules).update);
      }
      if (!whole) continue;
      mtg::episode_result_t result{};
      bus::fill_result(judge.verdict(), result);
      set_verdict(row, result);
    }
    if (verdict_fingerprint(row) == verdict_fingerprint(original)) {
      ++report.identical;
    } else {
      report.differences.push_back("episode " + to_string(row.episode_id) + " (" + row.task_id + "): recorded " +
                                   (original.success ? "success" : original.cause) + " IP " +
                                   std::to_string(original.ip) + ", now " + (row.success ? "success" : row.cause) +
                                   " IP " + std::to_string(row.ip));
    }
    report.rows.push_back(std::move(row));
  }
  return report;
}

}  // namespace mtg::orchestrator
