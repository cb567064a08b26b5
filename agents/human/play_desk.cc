#include "agents/human/play_desk.h"

#include <algorithm>
#include <chrono>

#include "core/episode/outcomes.h"
#include "core/stats/intervals.h"

namespace mtg::agents {

using nlohmann::json;

AgentReply PlayDesk::reply(const mtg::episode_start_t& /*start*/, const mtg::observation_t& observation) {
  std::unique_lock lock(mutex_);
  awaiting_verdict_ = -1;  // a new observation: a verdict still missing is not waited for any longer
  current_ = observation;
  answer_.reset();
  between_steps_ = false;
  ++version_;
  changed_.notify_all();
  changed_.wait(lock, [&] { return answer_.has_value() || stopping_; });
  AgentReply reply;
  reply.provider = "human";
  // What the person was shown, as a model's usage counts the images sent to it.
  reply.usage.images_sent = static_cast<int>(observation.images.size());
  if (answer_) {
    reply.raw = *answer_;
  } else {
    reply.error = "the human agent stopped before answering";
  }
  current_.reset();
  answer_.reset();
  between_steps_ = !stopping_;
  ++version_;
  changed_.notify_all();
  return reply;
}

void PlayDesk::end(const mtg::episode_start_t& start) {
  const std::lock_guard lock(mutex_);
  ++episodes_done_;
  // The judge's verdict may come before or after the episode's end reaches the agent.
  const bool judged = last_verdict_.is_object() && last_verdict_["episode"] == start.header.episode_id &&
                      last_verdict_["attempt"] == start.header.attempt;
  awaiting_verdict_ = judged ? -1 : start.header.episode_id;
  between_steps_ = false;
  ++version_;
  changed_.notify_all();
}

void PlayDesk::verdict(const mtg::episode_result_t& r) {
  const std::lock_guard lock(mutex_);
  // The run engine tries these attempts again (as it does a result it cannot read): they are not
  // the person's result.
  const auto cause = episode::cause_from_string(r.cause);
  const bool retried = !cause || !episode::stage_from_string(r.stage) || episode::is_retried(*cause);
  last_verdict_ = {{"episode", r.header.episode_id}, {"attempt", r.header.attempt}, {"retried", retried},
                   {"success", r.success != 0}, {"ip", r.ip}, {"stage", r.stage}, {"cause", r.cause},
                   {"steps", r.steps}, {"detail", r.detail}};
  if (r.header.episode_id == awaiting_verdict_) awaiting_verdict_ = -1;
  if (!retried) {
    ++scored_;
    successes_ += r.success ? 1 : 0;
    ip_sum_ += r.ip;
  }
  ++version_;
  changed_.notify_all();
}

json PlayDesk::observation_locked() const {
  // A person plays few episodes: 5 of 6 is anywhere from 44 to 97 %, and the page says so.
  const stats::Interval sr_ci = stats::wilson_interval(successes_, scored_);
  const json score = {{"scored", scored_},
                      {"successes", successes_},
                      {"sr", scored_ > 0 ? 100.0 * successes_ / scored_ : 0.0},
                      {"sr_ci", {100.0 * sr_ci.low, 100.0 * sr_ci.high}},
                      {"ip", scored_ > 0 ? ip_sum_ / scored_ : 0.0}};
  if (!current_) {
    return {{"waiting", true}, {"episodes_done", episodes_done_}, {"version", version_},
            {"last_verdict", last_verdict_}, {"score", score}};
  }
  const mtg::observation_t& o = *current_;
  json actions = json::array();
  for (const auto& a : o.actions) actions.push_back({{"key", a.key}, {"description", a.description}});
  json images = json::array();
  for (std::size_t i = 0; i < o.images.size(); ++i) {
    // The version in the URL keeps the browser from showing a cached image of an earlier step.
    images.push_back({{"role", o.images[i].role}, {"caption", o.images[i].caption}, {"width", o.images[i].width},
                      {"height", o.images[i].height},
                      {"url", "/api/play/image/" + std::to_string(i) + "?v=" + std::to_string(version_)}});
  }
  return {{"waiting", false},
          {"version", version_},
          {"episode", o.header.episode_id},
          {"attempt", o.header.attempt},
          {"task_text", o.task_text},
          {"step", o.step},
          {"step_limit", o.step_limit},
          {"text", o.text},
          {"hint", o.hint},
          {"actions", actions},
          {"images", images},
          {"done", o.done != 0},
          {"episodes_done", episodes_done_},
          {"last_verdict", last_verdict_},
          {"score", score}};
}

json PlayDesk::observation() const {
  const std::lock_guard lock(mutex_);
  return observation_locked();
}

std::string PlayDesk::act(const std::string& key) {
  const std::lock_guard lock(mutex_);
  if (!current_ || answer_) return "no observation is waiting for an action";
  const auto& offered = current_->actions;
  if (std::none_of(offered.begin(), offered.end(), [&](const auto& a) { return a.key == key; })) {
    return "'" + key + "' is not one of the offered actions";
  }
  answer_ = key;
  changed_.notify_all();
  return "";
}

json PlayDesk::wait_change(std::int64_t version, int timeout_ms) const {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                    [&] { return stopping_ || (version_ != version && !between_steps_ && awaiting_verdict_ < 0); });
  return observation_locked();
}

std::optional<std::pair<std::string, std::vector<std::uint8_t>>> PlayDesk::image(int index) const {
  const std::lock_guard lock(mutex_);
  if (!current_ || index < 0 || index >= static_cast<int>(current_->images.size())) return std::nullopt;
  const auto& img = current_->images[static_cast<std::size_t>(index)];
  return std::make_pair(img.encoding, img.data);
}

void PlayDesk::shutdown() {
  const std::lock_guard lock(mutex_);
  stopping_ = true;
  changed_.notify_all();
}

}  // namespace mtg::agents
