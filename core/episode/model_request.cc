#include "core/episode/model_request.h"

namespace mtg::episode {
namespace {

using nlohmann::json;

const char* role_name(SentMessage::Role r) {
  switch (r) {
    case SentMessage::Role::kSystem: return "system";
    case SentMessage::Role::kUser: return "user";
    case SentMessage::Role::kAssistant: return "assistant";
  }
  return "user";
}

json image_json(const SentImage& i) {
  return {{"step", i.step}, {"index", i.index}, {"mime", i.mime}, {"width", i.width}, {"height", i.height},
          {"sha256", i.sha256}};
}

// The text a record holds for the user turn of its own step, or for the system message.
const json* own_text(const json& record, const std::string& role, int step) {
  if (!record.contains("messages")) return nullptr;
  for (const auto& m : record["messages"]) {
    if (m.value("role", "") == role && m.contains("text") && (role == "system" || m.value("step", -1) == step)) {
      return &m["text"];
    }
  }
  return nullptr;
}

}  // namespace

std::string request_record(const SentRequest& request, bool first) {
  json messages = json::array();
  for (const SentMessage& m : request.messages) {
    json j = {{"role", role_name(m.role)}};
    if (m.role != SentMessage::Role::kSystem) j["step"] = m.step;
    const bool written_here = (m.role == SentMessage::Role::kSystem && first) ||
                              (m.role == SentMessage::Role::kUser && m.step == request.step);
    if (written_here) j["text"] = m.text;
    if (!m.images.empty()) {
      json images = json::array();
      for (const auto& i : m.images) images.push_back(image_json(i));
      j["images"] = std::move(images);
    }
    messages.push_back(std::move(j));
  }
  json out = {{"step", request.step}, {"messages", std::move(messages)}};
  if (first) out["params"] = request.params;
  return out.dump();
}

std::map<int, json> resolve_requests(const std::map<int, std::string>& records,
                                     const std::map<int, std::string>& replies) {
  std::map<int, json> parsed;
  for (const auto& [step, text] : records) {
    if (text.empty()) continue;
    json j = json::parse(text, nullptr, false);
    parsed[step] = j.is_discarded() || !j.is_object() ? json{{"error", "the recorded request does not parse"}} : j;
  }
  // The attempt's first request carries the system text and the parameters.
  const json* system = nullptr;
  json params = nullptr;
  for (const auto& [step, r] : parsed) {
    if (r.contains("params")) {
      system = own_text(r, "system", step);
      params = r["params"];
      break;
    }
  }
  std::map<int, json> out;
  for (const auto& [step, r] : parsed) {
    if (r.contains("error")) {
      out[step] = r;
      continue;
    }
    json messages = json::array();
    for (const auto& m : r.value("messages", json::array())) {
      const std::string role = m.value("role", "");
      const int from = m.value("step", -1);
      json full = {{"role", role}, {"images", m.value("images", json::array())}};
      if (role != "system") full["step"] = from;
      const json* text = nullptr;
      std::string reply;
      bool have_reply = false;
      if (m.contains("text")) {
        text = &m["text"];
      } else if (role == "system") {
        text = system;
      } else if (role == "user") {
        const auto it = parsed.find(from);
        if (it != parsed.end()) text = own_text(it->second, "user", from);
      } else if (role == "assistant") {
        const auto it = replies.find(from);
        if (it != replies.end()) {
          reply = it->second;
          have_reply = true;
        }
      }
      if (have_reply) {
        full["text"] = reply;
      } else if (text != nullptr) {
        full["text"] = *text;
      } else {
        full["text"] = nullptr;
        full["missing"] = true;
      }
      messages.push_back(std::move(full));
    }
    out[step] = {{"step", step}, {"params", params}, {"messages", std::move(messages)}};
  }
  return out;
}

}  // namespace mtg::episode
