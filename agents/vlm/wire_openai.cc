// OpenAI chat completions (POST <base>/chat/completions), also spoken by vLLM, Ollama,
// llama.cpp's server and OpenRouter. Images go as data-URI image_url parts with a detail level.

#include <nlohmann/json.hpp>

#include "agents/vlm/wire.h"
#include "core/util/error.h"

namespace mtg::vlm::openai {

WireRequest build_request(const ModelSpec& spec, const GenerationParams& params,
                          std::span<const ChatMessage> messages) {
  nlohmann::json msgs = nlohmann::json::array();
  for (const ChatMessage& m : messages) {
    if (m.role == ChatMessage::Role::kSystem) {
      msgs.push_back({{"role", "system"}, {"content", m.text}});
    } else if (m.role == ChatMessage::Role::kAssistant) {
      msgs.push_back({{"role", "assistant"}, {"content", m.text}});
    } else {
      nlohmann::json parts = nlohmann::json::array();
      parts.push_back({{"type", "text"}, {"text", m.text}});
      for (const ImagePart& img : m.images) {
        parts.push_back({{"type", "image_url"},
                         {"image_url",
                          {{"url", "data:" + img.mime + ";base64," + img.base64}, {"detail", params.image_detail}}}});
      }
      msgs.push_back({{"role", "user"}, {"content", parts}});
    }
  }
  nlohmann::json body = {{"model", spec.model},
                         {"messages", msgs},
                         {"temperature", params.temperature},
                         {"max_tokens", params.max_output_tokens}};
  if (params.seed) body["seed"] = *params.seed;
  return {spec.base_url + "/chat/completions", body.dump()};
}

ModelAnswer parse_answer(const std::string& body) {
  const nlohmann::json j = nlohmann::json::parse(body);
  const nlohmann::json& choices = j.at("choices");
  if (!choices.is_array() || choices.empty()) throw Error("malformed response: no choices");
  const nlohmann::json& content = choices[0].at("message").at("content");
  ModelAnswer a;
  if (content.is_string()) {
    a.text = content.get<std::string>();
  } else if (content.is_array()) {  // some compatible servers answer in parts
    for (const auto& part : content) {
      if (part.is_object() && part.value("type", "") == "text") a.text += part.value("text", "");
    }
  } else if (!content.is_null()) {  // null: a refusal or an empty answer, which is a (bad) reply
    throw Error("malformed response: message content is neither text nor parts");
  }
  if (j.contains("usage") && j["usage"].is_object()) {
    a.input_tokens = j["usage"].value("prompt_tokens", 0);
    a.output_tokens = j["usage"].value("completion_tokens", 0);
  }
  return a;
}

}  // namespace mtg::vlm::openai
