#include "orchestrator/remote/run_announcement.h"

#include "core/util/error.h"
#include "core/util/hash.h"

namespace mtg::orchestrator::remote {

mtg::run_info_t announcement(const RuntimeConfig& run, const RunCounts& counts) {
  mtg::run_info_t m{};
  m.profile = run.profile;
  m.platform_rules = run.platform_rules == graph::PlatformRules::kWholeSurface ? mtg::run_info_t::RULES_WHOLE_SURFACE
                                                                               : mtg::run_info_t::RULES_REACHED_AND_SEEN;
  m.render = run.render;
  m.image_width = run.image_width;
  m.image_height = run.image_height;
  m.image_encoding = run.image_encoding;
  m.episode_timeout_s = run.episode_timeout_s;
  m.agents = run.agents;
  m.n_agents = static_cast<std::int16_t>(m.agents.size());
  m.vlm_args = run.vlm_args;
  m.n_vlm_args = static_cast<std::int16_t>(m.vlm_args.size());
  m.dataset_json = run.dataset_json;
  m.data_dir = run.data_dir;
  m.dataset_digest = run.dataset_json.empty() ? "" : to_hex(fnv1a64(run.dataset_json));
  m.allow_data_mismatch = run.allow_data_mismatch;
  m.planned = counts.planned;
  m.finished = counts.finished;
  m.scored = counts.scored;
  m.successes = counts.successes;
  m.ip_sum = counts.ip_sum;
  m.errors = counts.errors;
  m.in_flight = counts.in_flight;
  return m;
}

RuntimeConfig announced_config(const mtg::run_info_t& info) {
  RuntimeConfig c;
  c.run_id = info.header.run_id;
  c.profile = info.profile;
  switch (info.platform_rules) {
    case mtg::run_info_t::RULES_REACHED_AND_SEEN: c.platform_rules = graph::PlatformRules::kReachedAndSeen; break;
    case mtg::run_info_t::RULES_WHOLE_SURFACE: c.platform_rules = graph::PlatformRules::kWholeSurface; break;
    default: throw Error("run announcement: unknown platform_rules " + std::to_string(info.platform_rules));
  }
  c.render = info.render;
  c.image_width = info.image_width;
  c.image_height = info.image_height;
  c.image_encoding = info.image_encoding;
  c.episode_timeout_s = info.episode_timeout_s;
  c.agents = info.agents;
  c.vlm_args = info.vlm_args;
  c.dataset_json = info.dataset_json;
  c.data_dir = info.data_dir;
  c.allow_data_mismatch = info.allow_data_mismatch;
  return c;
}

}  // namespace mtg::orchestrator::remote
