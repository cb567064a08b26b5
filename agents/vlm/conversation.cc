#include "agents/vlm/conversation.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "agents/vlm/encoding.h"
#include "core/render/codec_module.h"
#include "core/episode/rules.h"
#include "core/util/error.h"

namespace mtg::vlm {
namespace {

std::string role_legend(const std::string& role) {
  if (role == "view_marked") return "the platform from where you stand, objects or free spaces numbered as the keys";
  if (role == "view_zoom") return "a close-up of a crowded part of the platform, objects numbered as the keys";
  if (role == "view") return "the platform from where you stand, without numbers";
  if (role == "item") return "the object in your hand";
  if (role == "focus") return "a close-up of an object the task names, numbered as its key, other objects faded";
  if (role == "topdown_marked") return "the apartment from above, platforms numbered as the l keys";
  if (role == "topdown") return "the apartment from above";
  return role;
}

bool wanted(const VlmSettings& s, const std::string& role) {
  return std::find(s.image_roles.begin(), s.image_roles.end(), role) != s.image_roles.end();
}

}  // namespace

std::vector<OutgoingImage> images_to_send(const mtg::observation_t& obs, const VlmSettings& settings) {
  std::vector<OutgoingImage> out;
  for (std::size_t i = 0; i < obs.images.size(); ++i) {
    const mtg::image_t& img = obs.images[i];
    if (!wanted(settings, img.role) || img.data.empty()) continue;
    OutgoingImage o;
    o.part.mime = img.encoding == "jpeg" ? "image/jpeg" : "image/png";
    o.sent = {obs.step, static_cast<int>(i), o.part.mime, img.width, img.height, ""};
    const int longest = std::max(img.width, img.height);
    std::vector<std::uint8_t> bytes;
    if (settings.image_max_side > 0 && longest > settings.image_max_side) {
      const cv::Mat decoded = render::decode_color_image(img.data);
      if (decoded.empty()) throw Error("observation image '" + img.role + "' (" + img.encoding + ") cannot be decoded");
      const double f = static_cast<double>(settings.image_max_side) / longest;
      cv::Mat small;
      cv::resize(decoded, small, cv::Size(), f, f, cv::INTER_AREA);
      render::encode_with_imgcodecs(img.encoding == "jpeg" ? ".jpg" : ".png", small, bytes);
      o.sent.width = small.cols;
      o.sent.height = small.rows;
    }
    const std::vector<std::uint8_t>& sent = bytes.empty() ? img.data : bytes;
    o.part.base64 = base64_encode(sent);
    o.sent.sha256 = sha256_hex({reinterpret_cast<const char*>(sent.data()), sent.size()});
    out.push_back(std::move(o));
  }
  return out;
}

std::string step_text(const PromptSet& prompts, const VlmSettings& settings, const mtg::observation_t& obs) {
  std::string actions;
  for (const auto& a : obs.actions) actions += "- " + a.key + ": " + a.description + "\n";
  std::string images;
  int n = 0;
  for (const mtg::image_t& img : obs.images) {
    if (wanted(settings, img.role) && !img.data.empty()) {
      images += "Image " + std::to_string(++n) + ": " + role_legend(img.role) + "." +
                (img.caption.empty() ? std::string() : " " + img.caption) + "\n";
    }
  }
  const std::map<std::string, std::string> vars = {
      {"task", obs.task_text},
      {"step", std::to_string(obs.step + 1)},
      {"steps_used", std::to_string(obs.step)},
      {"step_limit", std::to_string(obs.step_limit)},
      {"situation", obs.text},
      {"hint", obs.hint.empty() ? "" : "Feedback on your last action: " + obs.hint},
      {"actions", actions},
      {"images", images}};
  return render_template(prompts.step, vars, prompts.dir + "/step.txt");
}

Conversation::Conversation(const PromptSet& prompts, const VlmSettings& settings, const mtg::episode_start_t& start)
    : prompts_(prompts), settings_(settings) {
  system_.role = ChatMessage::Role::kSystem;
  system_.text = render_template(
      prompts.system,
      {{"step_limit", std::to_string(start.step_limit)}, {"directions", episode::direction_convention()}},
      prompts.dir + "/system.txt");
}

namespace {

nlohmann::json request_params(const VlmSettings& s) {
  nlohmann::json p = {{"temperature", s.temperature},       {"max_output_tokens", s.max_output_tokens},
                      {"image_detail", s.image_detail},     {"image_max_side", s.image_max_side},
                      {"image_roles", s.image_roles},       {"history_steps", s.history_steps},
                      {"history_images", s.history_images}};
  if (s.seed >= 0) p["seed"] = s.seed;
  return p;
}

}  // namespace

std::vector<ChatMessage> Conversation::ask(const mtg::observation_t& obs) {
  ChatMessage user;
  user.role = ChatMessage::Role::kUser;
  user.text = step_text(prompts_, settings_, obs);
  episode::SentMessage sent{episode::SentMessage::Role::kUser, obs.step, user.text, {}};
  for (auto& image : images_to_send(obs, settings_)) {
    user.images.push_back(std::move(image.part));
    sent.images.push_back(std::move(image.sent));
  }
  turns_.push_back(std::move(user));
  sent_.push_back(std::move(sent));

  // The last history_steps earlier (user, assistant) pairs, then this step's question.
  const std::size_t steps = (turns_.size() - 1) / 2;
  const std::size_t kept = settings_.history_steps == 0 ? steps
                                                        : std::min<std::size_t>(steps, settings_.history_steps);
  const std::size_t first = turns_.size() - 1 - 2 * kept;
  std::vector<ChatMessage> out = {system_};
  episode::SentRequest request{obs.step, {{episode::SentMessage::Role::kSystem, -1, system_.text, {}}},
                               request_params(settings_)};
  for (std::size_t i = first; i < turns_.size(); ++i) {
    out.push_back(turns_[i]);
    request.messages.push_back(sent_[i]);
    // Images stay only on the newest history_images user turns.
    const std::size_t age = (turns_.size() - 1 - i) / 2;
    if (age >= static_cast<std::size_t>(settings_.history_images)) {
      out.back().images.clear();
      request.messages.back().images.clear();
    }
  }
  last_request_ = episode::request_record(request, turns_.size() == 1);
  return out;
}

void Conversation::answered(const std::string& reply) {
  ChatMessage a;
  a.role = ChatMessage::Role::kAssistant;
  a.text = reply;
  turns_.push_back(std::move(a));
  sent_.push_back({episode::SentMessage::Role::kAssistant, sent_.back().step, "", {}});
}

}  // namespace mtg::vlm
