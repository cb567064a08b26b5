// Gemini generateContent (POST <base>/v1beta/models/<model>:generateContent). Roles are "user"
// and "model"; the system prompt is systemInstruction; images are inline_data parts.

#include <nlohmann/json.hpp>

#include "agents/vlm/wire.h"
#include "core/util/error.h"

namespace mtg::vlm::gemini {

WireRequest build_request(const ModelSpec& spec, const GenerationParams& params,
                          std::span<const ChatMessage> messages) {
  const std::string system = system_text(messages);
  nlohmann::json contents = nlohmann::json::array();
  for (const ChatMessage& m : messages) {
    if (m.role == ChatMessage::Role::kSystem) continue;
    nlohmann::json parts = nlohmann::json::array();
    parts.push_back({{"text", m.text}});
    for (const ImagePart& img : m.images) {
      parts.push_back({{"inline_data", {{"mime_type", img.mime}, {"data", img.base64}}}});
    }
    contents.push_back({{"role", m.role == ChatMessage::Role::kAssistant ? "model" : "user"}, {"parts", parts}});
  }
  nlohmann::json body = {
      {"contents", contents},
      {"generationConfig", {{"temperature", params.temperature}, {"maxOutputTokens", params.max_output_tokens}}}};
  if (!system.empty()) body["systemInstruction"] = {{"parts", nlohmann::json::array({{{"text", system}}})}};
  return {spec.base_url + "/v1beta/models/" + spec.model + ":generateContent", body.dump()};
}

ModelAnswer parse_answer(const std::string& body) {
  const nlohmann::json j = nlohmann::json::parse(body);
  if (!j.is_object()) throw Error("malformed response: not a JSON object");
  ModelAnswer a;
  // No candidate (a blocked prompt) or a candidate without parts (a safety stop) is an empty
  // reply: the model answered, just not with an action.
  if (j.contains("candidates") && j["candidates"].is_array() && !j["candidates"].empty()) {
    const nlohmann::json& c = j["candidates"][0];
    if (c.contains("content") && c["content"].contains("parts")) {
      for (const auto& part : c["content"]["parts"]) {
        if (part.is_object() && part.contains("text")) a.text += part["text"].get<std::string>();
      }
    }
  } else if (!j.contains("promptFeedback")) {
    throw Error("malformed response: no candidates");
  }
  if (j.contains("usageMetadata") && j["usageMetadata"].is_object()) {
    a.input_tokens = j["usageMetadata"].value("promptTokenCount", 0);
    a.output_tokens = j["usageMetadata"].value("candidatesTokenCount", 0);
  }
  return a;
}

}  // namespace mtg::vlm::gemini
