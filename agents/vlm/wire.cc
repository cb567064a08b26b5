#include "agents/vlm/wire.h"

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>

#include "core/util/error.h"

namespace mtg::vlm {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// "20s", "1.5s" (Gemini's protobuf Duration as JSON).
double duration_ms(const std::string& s) {
  if (s.empty() || s.back() != 's') return -1.0;
  try {
    return 1000.0 * std::stod(s.substr(0, s.size() - 1));
  } catch (const std::exception&) {
    return -1.0;
  }
}

}  // namespace

std::string system_text(std::span<const ChatMessage> messages) {
  std::string system;
  for (const ChatMessage& m : messages) {
    if (m.role == ChatMessage::Role::kSystem) system += (system.empty() ? "" : "\n\n") + m.text;
  }
  return system;
}

WireRequest build_request(const ModelSpec& spec, const GenerationParams& params,
                          std::span<const ChatMessage> messages) {
  switch (spec.provider) {
    case Provider::kAnthropic: return anthropic::build_request(spec, params, messages);
    case Provider::kGemini: return gemini::build_request(spec, params, messages);
    case Provider::kOpenAi:
    case Provider::kOpenAiCompatible: return openai::build_request(spec, params, messages);
  }
  throw InternalError("unknown provider");
}

std::vector<std::pair<std::string, std::string>> request_headers(const ModelSpec& spec, const ApiKey& key) {
  std::vector<std::pair<std::string, std::string>> h = {{"Content-Type", "application/json"}};
  switch (spec.provider) {
    case Provider::kAnthropic:
      h.emplace_back("x-api-key", key.reveal());
      h.emplace_back("anthropic-version", "2023-06-01");
      break;
    case Provider::kGemini:
      h.emplace_back("x-goog-api-key", key.reveal());  // in a header, so URLs in logs carry no key
      break;
    case Provider::kOpenAi:
    case Provider::kOpenAiCompatible:
      if (!key.empty()) h.emplace_back("Authorization", "Bearer " + key.reveal());
      break;
  }
  return h;
}

ModelAnswer parse_answer(const ModelSpec& spec, const std::string& body) {
  try {
    switch (spec.provider) {
      case Provider::kAnthropic: return anthropic::parse_answer(body);
      case Provider::kGemini: return gemini::parse_answer(body);
      case Provider::kOpenAi:
      case Provider::kOpenAiCompatible: return openai::parse_answer(body);
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("malformed response: ") + e.what());
  }
  throw InternalError("unknown provider");
}

ErrorInfo parse_error(const ModelSpec& /*spec*/, const std::string& body) {
  // The three providers agree on {"error": {"message": ..., and a type, code or status}}.
  ErrorInfo info;
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("error")) {
    info.message = body.substr(0, 200);
    return info;
  }
  const nlohmann::json& e = j["error"];
  if (e.is_string()) {
    info.message = e.get<std::string>();
    return info;
  }
  if (!e.is_object()) return info;
  if (e.contains("message") && e["message"].is_string()) info.message = e["message"];
  for (const char* key : {"code", "type", "status"}) {
    if (e.contains(key) && e[key].is_string()) info.code += (info.code.empty() ? "" : " ") + lower(e[key]);
  }
  if (e.contains("details") && e["details"].is_array()) {
    for (const auto& d : e["details"]) {
      if (d.is_object() && d.contains("retryDelay") && d["retryDelay"].is_string()) {
        info.retry_delay_ms = duration_ms(d["retryDelay"]);
      }
    }
  }
  return info;
}

}  // namespace mtg::vlm
