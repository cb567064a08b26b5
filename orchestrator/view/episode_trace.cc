#include "orchestrator/view/episode_trace.h"

#include <algorithm>
#include <map>
#include <set>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/observation_packing.h"
#include "core/episode/model_request.h"
#include "core/episode/outcomes.h"
#include "core/util/error.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_result_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"
#include "mtg/error_event_t.hpp"
#include "mtg/judge_event_t.hpp"
#include "mtg/observation_t.hpp"

namespace mtg::orchestrator::view {
namespace {

using bus::EpisodeStream;
using nlohmann::json;

template <class Msg>
Msg decode(const RecordedMessage& m) {
  Msg msg{};
  if (msg.decode(m.data.data(), 0, static_cast<int>(m.data.size())) < 0) {
    // Most often a recording made by a build of another schema: say so rather than "corrupt".
    const auto header = bus::peek_header(m.data);
    if (header && !bus::speaks_our_schema(*header)) {
      throw Error(bus::schema_mismatch(*header, "the recorded message on " + m.channel) +
                  "; open it with the build that recorded it");
    }
    throw Error("a recorded message on " + m.channel + " does not decode");
  }
  return msg;
}

int attempt_of(const RecordedMessage& m) {
  const auto header = bus::peek_header(m.data);
  return header ? header->attempt : -1;
}

int pick_attempt(const std::vector<RecordedMessage>& messages, int attempt) {
  if (attempt >= 0) return attempt;
  const auto attempts = recorded_attempts(messages);
  return attempts.empty() ? 0 : attempts.back();
}

json parse_or_text(const std::string& text) {
  json j = json::parse(text, nullptr, false);
  return j.is_discarded() ? json(text) : j;
}

json observation_json(const mtg::observation_t& obs) {
  json actions = json::array();
  for (const auto& a : obs.actions) actions.push_back({{"key", a.key}, {"description", a.description}});
  json images = json::array();
  for (std::size_t i = 0; i < obs.images.size(); ++i) {
    const auto& img = obs.images[i];
    images.push_back({{"index", i}, {"role", img.role}, {"caption", img.caption}, {"encoding", img.encoding}, {"width", img.width},
                      {"height", img.height}, {"bytes", img.nbytes}});
  }
  // The task as the agent read it (under the look-alike aid "image" not the stored text).
  return {{"task_text", obs.task_text}, {"text", obs.text}, {"hint", obs.hint}, {"actions", actions}, {"images", images}};
}

json action_json(const mtg::agent_action_t& a) {
  return {{"raw_reply", a.raw_reply},     {"parsed_key", a.parsed_key},     {"format_ok", a.format_ok != 0},
          {"error", a.error},             {"provider", a.provider},         {"model", a.model},
          {"input_tokens", a.input_tokens}, {"output_tokens", a.output_tokens}, {"cost_usd", a.cost_usd},
          {"latency_ms", a.latency_ms},   {"cache_hit", a.cache_hit != 0},       {"prompt_version", a.prompt_version}};
}

json result_json(const mtg::episode_result_t& r) {
  json subtasks = json::array();
  for (std::size_t i = 0; i < r.subtask_ip.size(); ++i) {
    subtasks.push_back({{"ip", r.subtask_ip[i]}, {"success", i < r.subtask_success.size() && r.subtask_success[i] != 0}});
  }
  return {{"success", r.success != 0},
          {"ip", r.ip},
          {"stage", r.stage},
          {"stage_text", episode::explain_stage(r.stage)},
          {"cause", r.cause},
          {"cause_text", episode::explain_cause(r.cause)},
          {"steps", r.steps},
          {"invalid_actions", r.invalid_actions},
          {"input_tokens", r.input_tokens},
          {"output_tokens", r.output_tokens},
          {"cost_usd", r.cost_usd},
          {"model_calls", r.model_calls},
          {"subtasks", subtasks},
          {"detail", r.detail}};
}

}  // namespace

std::vector<int> recorded_attempts(const std::vector<RecordedMessage>& messages) {
  std::set<int> attempts;
  for (const auto& m : messages) {
    if (m.channel == bus::kEpisodeStart) attempts.insert(attempt_of(m));
  }
  return {attempts.begin(), attempts.end()};
}

json episode_trace(bus::EpisodeId episode_id, const std::vector<RecordedMessage>& messages, int attempt) {
  attempt = pick_attempt(messages, attempt);
  json out = {{"episode_id", episode_id.value()}, {"attempt", attempt}, {"attempts", recorded_attempts(messages)},
              {"task", nullptr}, {"result", nullptr}, {"errors", json::array()}};
  std::map<int, json> steps;  // by step number
  std::map<int, std::string> requests, replies;  // model agents' records, by step
  bus::WordsCodec codec;
  bus::ObservationReader reader;  // the attempt's observations, whole
  auto step_of = [&](int step) -> json& {
    json& s = steps[step];
    if (s.is_null()) s = {{"step", step}, {"done", false}, {"observation", nullptr}, {"action", nullptr},
                          {"judge", json::array()}};
    return s;
  };
  for (const auto& m : messages) {
    if (attempt_of(m) != attempt) continue;
    if (m.channel == bus::kEpisodeStart) {
      const auto start = decode<mtg::episode_start_t>(m);
      out["task"] = {{"task_id", start.task.task_id}, {"scene", start.task.scene}, {"level", start.task.level},
                     {"task_type", start.task.task_type}, {"text", start.task.text}};
      out["agent"] = start.agent;
      out["seed"] = start.seed;
      out["step_limit"] = start.step_limit;
      out["render"] = start.render != 0;
    } else if (m.channel == bus::kEpisodeResult) {
      out["result"] = result_json(decode<mtg::episode_result_t>(m));
    } else if (m.channel == bus::kError) {
      const auto e = decode<mtg::error_event_t>(m);
      out["errors"].push_back({{"source", e.source}, {"severity", e.severity}, {"message", e.message}});
    } else if (bus::is_episode_channel(m.channel, EpisodeStream::kObservation)) {
      mtg::observation_t obs;
      try {
        obs = reader.whole(decode<mtg::observation_t>(m), codec);
      } catch (const Error& e) {  // what it refers to is not in the recording
        out["errors"].push_back({{"source", "recording"}, {"severity", "error"}, {"message", e.what()}});
        continue;
      }
      json& s = step_of(obs.step);
      // The first copy of a step is what the agent answered (a late renderer may send a second).
      if (!s["observation"].is_null()) continue;
      s["done"] = obs.done != 0;
      s["observation"] = observation_json(obs);
    } else if (bus::is_episode_channel(m.channel, EpisodeStream::kAction)) {
      const auto a = decode<mtg::agent_action_t>(m);
      step_of(a.step)["action"] = action_json(a);
      requests[a.step] = a.request;
      replies[a.step] = a.raw_reply;
    } else if (bus::is_episode_channel(m.channel, EpisodeStream::kJudge)) {
      const auto e = decode<mtg::judge_event_t>(m);
      step_of(e.step)["judge"].push_back({{"kind", e.kind}, {"subtask", e.subtask}, {"milestone", e.milestone},
                                          {"ip", e.ip}, {"text", e.text}});
    }
  }
  // What a model received at each step, in full, and its reply with the chosen key's meaning.
  const auto resolved = episode::resolve_requests(requests, replies);
  json list = json::array();
  for (auto& [step, s] : steps) {
    const auto r = resolved.find(step);
    s["request"] = r == resolved.end() ? json(nullptr) : r->second;
    s["reply"] = nullptr;
    if (!s["action"].is_null()) {
      const json& a = s["action"];
      json meaning = nullptr;
      if (!s["observation"].is_null()) {
        for (const auto& option : s["observation"]["actions"]) {
          if (option["key"] == a["parsed_key"]) meaning = option["description"];
        }
      }
      s["reply"] = {{"text", a["raw_reply"]}, {"parsed_key", a["parsed_key"]}, {"meaning", meaning}};
    }
    list.push_back(std::move(s));
  }
  out["steps"] = std::move(list);
  return out;
}

void link_images(json& episode, const std::function<std::string(int step, int index)>& url_of) {
  std::map<std::pair<int, int>, bool> recorded;  // (step, index) -> bytes present
  for (json& step : episode["steps"]) {
    if (step["observation"].is_null()) continue;
    const int n = step["step"].get<int>();
    for (json& img : step["observation"]["images"]) {
      const bool present = img["bytes"].get<int>() > 0;
      recorded[{n, img["index"].get<int>()}] = present;
      img["url"] = present ? json(url_of(n, img["index"].get<int>())) : json(nullptr);
    }
  }
  for (json& step : episode["steps"]) {
    if (!step.contains("request") || !step["request"].is_object() || !step["request"].contains("messages")) continue;
    for (json& m : step["request"]["messages"]) {
      for (json& img : m["images"]) {
        const std::pair<int, int> at = {img.value("step", -1), img.value("index", -1)};
        const auto it = recorded.find(at);
        img["url"] = it != recorded.end() && it->second ? json(url_of(at.first, at.second)) : json(nullptr);
      }
    }
  }
}

json episode_truth(const std::vector<RecordedMessage>& messages, int attempt, const bus::RecordedTruths& answers) {
  attempt = pick_attempt(messages, attempt);
  for (const auto& m : messages) {
    if (m.channel != bus::kEpisodeTruth || attempt_of(m) != attempt) continue;
    const auto truth = answers.open(decode<mtg::episode_truth_t>(m));
    return {{"task_id", truth.task_id}, {"goal", parse_or_text(truth.goal_json)},
            {"oracle_plan", truth.oracle_plan}, {"identify", parse_or_text(truth.identify_json)}};
  }
  return nullptr;
}

std::optional<RecordedImage> observation_image(const std::vector<RecordedMessage>& messages, int attempt, int step,
                                               int index) {
  attempt = pick_attempt(messages, attempt);
  bus::WordsCodec codec;
  bus::ObservationReader reader;
  for (const auto& m : messages) {
    if (!bus::is_episode_channel(m.channel, EpisodeStream::kObservation) || attempt_of(m) != attempt) continue;
    const auto packed = decode<mtg::observation_t>(m);
    if (packed.step > step) break;  // images refer only to earlier steps
    const auto obs = reader.whole(packed, codec);
    if (obs.step != step) continue;  // the first copy of the step, as episode_trace shows it
    if (index < 0 || index >= static_cast<int>(obs.images.size())) return std::nullopt;
    const auto& img = obs.images[static_cast<std::size_t>(index)];
    if (img.nbytes == 0) return std::nullopt;
    return RecordedImage{img.encoding, img.data};
  }
  return std::nullopt;
}

std::map<std::pair<int, int>, RecordedImage> observation_images(const std::vector<RecordedMessage>& messages,
                                                                int attempt) {
  attempt = pick_attempt(messages, attempt);
  std::map<std::pair<int, int>, RecordedImage> out;
  std::set<int> seen;  // steps: the first copy of each, as episode_trace shows it
  bus::WordsCodec codec;
  bus::ObservationReader reader;
  for (const auto& m : messages) {
    if (!bus::is_episode_channel(m.channel, EpisodeStream::kObservation) || attempt_of(m) != attempt) continue;
    mtg::observation_t obs;
    try {
      obs = reader.whole(decode<mtg::observation_t>(m), codec);
    } catch (const Error&) {
      continue;  // refers to what the recording lacks: episode_trace says so
    }
    if (!seen.insert(obs.step).second) continue;
    for (std::size_t i = 0; i < obs.images.size(); ++i) {
      const auto& img = obs.images[i];
      if (img.nbytes > 0) out[{obs.step, static_cast<int>(i)}] = RecordedImage{img.encoding, img.data};
    }
  }
  return out;
}

}  // namespace mtg::orchestrator::view
