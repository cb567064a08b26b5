#include "bus/convert.h"

#include "core/util/error.h"
#include "core/util/hash.h"

namespace mtg::bus {
namespace {

graph::ObjectId object_id(const graph::SceneGraph& g, const std::string& name) {
  if (name.empty()) return {};
  const graph::ObjectId i = g.find_object(name);
  if (!i.valid()) throw Error("state update: unknown object '" + name + "' in scene " + g.scene);
  return i;
}

graph::PlatformId platform_id(const graph::SceneGraph& g, const std::string& name) {
  if (name.empty()) return {};
  const graph::PlatformId i = g.find_platform(name);
  if (!i.valid()) throw Error("state update: unknown platform '" + name + "' in scene " + g.scene);
  return i;
}

std::string object_name(const graph::SceneGraph& g, graph::ObjectId i) {
  return i.valid() ? g.objects[i].name : std::string();
}
std::string platform_name(const graph::SceneGraph& g, graph::PlatformId i) {
  return i.valid() ? g.platforms[i].name : std::string();
}

}  // namespace

mtg::task_t to_message(const tasks::Task& t) {
  mtg::task_t m{};
  m.task_id = t.id;
  m.scene = t.scene;
  m.level = static_cast<int8_t>(t.level);
  m.task_type = t.type;
  m.text = t.text;
  return m;
}

mtg::episode_truth_t truth_message(const tasks::Task& t) {
  mtg::episode_truth_t m{};
  m.task_id = t.id;
  m.goal_json = t.goal.dump();
  m.n_oracle = static_cast<int16_t>(t.oracle.size());
  m.oracle_plan = t.oracle;
  m.identify_json = tasks::to_json(t.identify).dump();
  return m;
}

EpisodeTask from_messages(const mtg::task_t& m, const mtg::episode_truth_t& truth) {
  if (truth.task_id != m.task_id) {
    throw Error("episode truth for task " + truth.task_id + " does not belong to task " + m.task_id);
  }
  EpisodeTask t;
  t.id = m.task_id;
  t.scene = m.scene;
  t.level = m.level;
  t.type = m.task_type;
  t.text = m.text;
  try {
    t.goal = nlohmann::json::parse(truth.goal_json);
    if (!truth.identify_json.empty()) t.identify = tasks::identifications_from_json(nlohmann::json::parse(truth.identify_json));
  } catch (const nlohmann::json::exception&) {
    throw Error("task " + m.task_id + ": goal_json or identify_json is not JSON");
  }
  t.oracle = truth.oracle_plan;
  return t;
}

mtg::state_update_t to_message(const graph::SceneGraph& g, const episode::WorldState& s,
                               const episode::StateUpdate& u) {
  mtg::state_update_t m{};
  m.step = u.step;
  m.key = u.key;
  m.at_platform = platform_name(g, u.at_platform);
  m.side = static_cast<int8_t>(u.side);
  m.holding = object_name(g, u.holding);
  m.picked = object_name(g, u.picked);
  for (const episode::Placement& p : u.placed) {
    mtg::object_placement_t op{};
    op.object = object_name(g, p.object);
    op.platform = platform_name(g, p.platform);
    op.x = p.position.x();
    op.y = p.position.y();
    op.z = p.position.z();
    const geom::Ring& fp = s.objects[p.object].footprint;
    op.n_vertices = static_cast<int32_t>(fp.size());
    for (const auto& q : fp) {
      op.footprint_x.push_back(q.x());
      op.footprint_y.push_back(q.y());
    }
    m.moved.push_back(std::move(op));
  }
  m.n_moved = static_cast<int32_t>(m.moved.size());
  m.invalid = u.invalid;
  m.format_error = u.format_error;
  m.provider_error = u.provider_error;
  m.done = u.done;
  m.end_reason = episode::to_string(u.end_reason);
  return m;
}

episode::StateUpdate from_message(const graph::SceneGraph& g, const mtg::state_update_t& m) {
  episode::StateUpdate u;
  u.step = m.step;
  u.key = m.key;
  u.at_platform = platform_id(g, m.at_platform);
  u.side = m.side;
  u.holding = object_id(g, m.holding);
  u.picked = object_id(g, m.picked);
  for (const auto& op : m.moved) {
    u.placed.push_back({object_id(g, op.object), platform_id(g, op.platform), Eigen::Vector3d(op.x, op.y, op.z)});
  }
  u.invalid = m.invalid;
  u.format_error = m.format_error;
  u.provider_error = m.provider_error;
  u.done = m.done;
  const auto reason = episode::end_reason_from_string(m.end_reason);
  if (!reason) throw Error("state update: unknown end_reason '" + m.end_reason + "'");
  u.end_reason = *reason;
  return u;
}

episode::RuleOptions episode_rules(const mtg::episode_start_t& start) {
  episode::RuleOptions rules;
  if (start.step_limit > 0) rules.step_limit = start.step_limit;
  rules.object_names = start.object_names;
  switch (start.lookalike_aid) {
    case mtg::episode_start_t::AID_BOTH: rules.lookalike_aid = episode::LookalikeAid::kBoth; break;
    case mtg::episode_start_t::AID_IMAGE: rules.lookalike_aid = episode::LookalikeAid::kImage; break;
    case mtg::episode_start_t::AID_WORDS: rules.lookalike_aid = episode::LookalikeAid::kWords; break;
    default:
      throw Error("episode start: unknown lookalike_aid " + std::to_string(start.lookalike_aid));
  }
  switch (start.numbering) {
    case mtg::episode_start_t::NUMBERING_STABLE: rules.numbering = episode::Numbering::kStable; break;
    case mtg::episode_start_t::NUMBERING_PER_STATE: rules.numbering = episode::Numbering::kPerState; break;
    default:
      throw Error("episode start: unknown numbering " + std::to_string(start.numbering));
  }
  return rules;
}

std::int8_t to_message(episode::LookalikeAid aid) {
  switch (aid) {
    case episode::LookalikeAid::kBoth: return mtg::episode_start_t::AID_BOTH;
    case episode::LookalikeAid::kImage: return mtg::episode_start_t::AID_IMAGE;
    case episode::LookalikeAid::kWords: return mtg::episode_start_t::AID_WORDS;
  }
  return mtg::episode_start_t::AID_BOTH;
}

std::int8_t to_message(episode::Numbering numbering) {
  return numbering == episode::Numbering::kStable ? mtg::episode_start_t::NUMBERING_STABLE
                                                  : mtg::episode_start_t::NUMBERING_PER_STATE;
}

episode::AgentAnswer to_answer(const mtg::agent_action_t& action) {
  return {action.parsed_key, action.format_ok != 0, !action.error.empty()};
}

mtg::world_state_delta_t to_message(const episode::StateDelta& d) {
  mtg::world_state_delta_t m{};
  m.phase = static_cast<int8_t>(d.phase);
  m.at_platform = d.at;
  m.side = static_cast<int8_t>(d.side);
  m.held = d.held;
  m.steps = d.steps;
  for (const episode::MovedObject& o : d.moved) {
    mtg::moved_object_t mo{};
    mo.object = o.object;
    mo.parent = o.parent;
    for (int k = 0; k < 3; ++k) mo.position[k] = o.position[k];
    for (const geom::Point2& q : o.footprint) {
      mo.footprint_x.push_back(q.x());
      mo.footprint_y.push_back(q.y());
    }
    mo.n_vertices = static_cast<int32_t>(o.footprint.size());
    mo.bottom = o.bottom;
    mo.top = o.top;
    mo.placed_side = static_cast<int8_t>(o.placed_side);
    m.moved.push_back(std::move(mo));
  }
  m.n_moved = static_cast<int32_t>(m.moved.size());
  for (const episode::PlatformOrder& p : d.reordered) {
    m.reordered.push_back({p.platform, static_cast<int32_t>(p.objects.size()), p.objects});
  }
  m.n_reordered = static_cast<int32_t>(m.reordered.size());
  for (const episode::PlatformOffset& p : d.offsets) {
    mtg::platform_offset_t mo{};
    mo.platform = p.platform;
    for (int k = 0; k < 3; ++k) mo.offset[k] = p.offset[k];
    m.offsets.push_back(std::move(mo));
  }
  m.n_offsets = static_cast<int32_t>(m.offsets.size());
  m.numbering = to_message(d.numbering);
  for (const episode::PlatformOrder& p : d.numbered) {
    m.numbered.push_back({p.platform, static_cast<int32_t>(p.objects.size()), p.objects});
  }
  m.n_numbered = static_cast<int32_t>(m.numbered.size());
  return m;
}

episode::StateDelta from_message(const mtg::world_state_delta_t& m) {
  episode::StateDelta d;
  d.phase = static_cast<episode::Phase>(m.phase);  // episode::apply_delta checks the range
  d.at = m.at_platform;
  d.side = m.side;
  d.held = m.held;
  d.steps = m.steps;
  for (const mtg::moved_object_t& mo : m.moved) {
    episode::MovedObject o;
    o.object = mo.object;
    o.parent = mo.parent;
    o.position = Eigen::Vector3d(mo.position[0], mo.position[1], mo.position[2]);
    if (mo.footprint_x.size() != mo.footprint_y.size()) {
      throw Error("world state: footprint of '" + mo.object + "' has " + std::to_string(mo.footprint_x.size()) +
                  " x but " + std::to_string(mo.footprint_y.size()) + " y coordinates");
    }
    for (std::size_t k = 0; k < mo.footprint_x.size(); ++k) o.footprint.emplace_back(mo.footprint_x[k], mo.footprint_y[k]);
    o.bottom = mo.bottom;
    o.top = mo.top;
    o.placed_side = mo.placed_side;
    d.moved.push_back(std::move(o));
  }
  for (const mtg::platform_order_t& p : m.reordered) d.reordered.push_back({p.platform, p.objects});
  for (const mtg::platform_offset_t& p : m.offsets) {
    d.offsets.push_back({p.platform, Eigen::Vector3d(p.offset[0], p.offset[1], p.offset[2])});
  }
  // episode::apply_delta checks the value.
  d.numbering = static_cast<episode::Numbering>(m.numbering);
  for (const mtg::platform_order_t& p : m.numbered) d.numbered.push_back({p.platform, p.objects});
  return d;
}

render::ImageRequest from_message(const mtg::render_request_t& m) {
  render::ImageRequest r;
  r.scene = m.scene;
  r.data_dir = m.data_dir;
  r.width = m.width;
  r.height = m.height;
  r.encoding = m.encoding;
  r.state = from_message(m.state);
  if (m.min_region_size > 0.0) r.min_region_size = m.min_region_size;
  for (const mtg::render_view_t& v : m.views) {
    r.views.push_back({render::parse_view_kind(v.view), v.platform, v.side, v.item, render::parse_mark_kind(v.marks),
                       v.number, v.caption});
  }
  return r;
}

mtg::render_view_t to_message(const graph::SceneGraph& g, const render::ViewRequest& v) {
  mtg::render_view_t m{};
  m.view = render::to_string(v.view);
  m.platform = platform_name(g, v.platform);
  m.side = static_cast<int8_t>(v.side);
  m.item = object_name(g, v.object);
  m.marks = render::to_string(v.marks);
  m.number = v.number;
  m.caption = v.caption;
  return m;
}

mtg::image_t to_message(const render::EncodedImage& e) {
  mtg::image_t img{};
  img.role = e.role;
  img.caption = e.caption;
  img.encoding = e.encoding;
  img.width = e.width;
  img.height = e.height;
  img.content_hash = to_hex(fnv1a64(e.bytes));
  img.data = e.bytes;
  img.nbytes = static_cast<int32_t>(img.data.size());
  return img;
}

void set_usage(mtg::agent_action_t& a, const episode::AnswerUsage& u) {
  a.input_tokens = u.input_tokens;
  a.output_tokens = u.output_tokens;
  a.images_sent = u.images_sent;
  a.cost_usd = u.cost_usd;
  a.latency_ms = u.latency_ms;
  a.cache_hit = u.cache_hit;
}

episode::AnswerUsage answer_usage(const mtg::agent_action_t& a) {
  return {a.input_tokens, a.output_tokens, a.images_sent, a.cost_usd, a.latency_ms, a.cache_hit != 0};
}

void set_usage(mtg::episode_result_t& r, const episode::EpisodeUsage& u) {
  r.input_tokens = static_cast<int32_t>(u.input_tokens);
  r.output_tokens = static_cast<int32_t>(u.output_tokens);
  r.images_sent = static_cast<int32_t>(u.images_sent);
  r.model_calls = static_cast<int32_t>(u.model_calls);
  r.cache_hits = static_cast<int32_t>(u.cache_hits);
  r.cost_usd = u.cost_usd;
  r.spent_usd = u.spent_usd;
  r.latency_ms = u.latency_ms;
  r.prompt_version = u.prompt_version;
}

episode::EpisodeUsage episode_usage(const mtg::episode_result_t& r) {
  episode::EpisodeUsage u;
  u.input_tokens = r.input_tokens;
  u.output_tokens = r.output_tokens;
  u.images_sent = r.images_sent;
  u.model_calls = r.model_calls;
  u.cache_hits = r.cache_hits;
  u.cost_usd = r.cost_usd;
  u.spent_usd = r.spent_usd;
  u.latency_ms = r.latency_ms;
  u.prompt_version = r.prompt_version;
  return u;
}

void fill_result(const episode::Verdict& v, mtg::episode_result_t& r) {
  r.success = v.success;
  r.ip = v.ip;
  r.stage = episode::to_string(v.stage);
  r.cause = episode::to_string(v.cause);
  r.steps = v.steps;
  r.invalid_actions = v.invalid_actions;
  r.n_subtasks = static_cast<int8_t>(v.part_ip.size());
  r.subtask_ip = v.part_ip;
  r.subtask_success.assign(v.part_success.begin(), v.part_success.end());
  r.detail = v.detail;
}

}  // namespace mtg::bus
