#pragma once
// Each provider's wire format: the request (URL, headers, JSON body) for a conversation, the
// answer in a response body, and what an error body says. One file per provider:
// wire_openai.cc (also every OpenAI-compatible server), wire_anthropic.cc, wire_gemini.cc.

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "agents/vlm/chat.h"
#include "agents/vlm/model_spec.h"
#include "agents/vlm/secrets.h"

namespace mtg::vlm {

struct WireRequest {
  std::string url;
  std::string body;  // JSON; with the URL, exactly what the response cache keys on
};

/// What an error response says, as far as it can be read.
struct ErrorInfo {
  std::string message;   // the provider's message ("" if none)
  std::string code;      // type / code / status, lower case (e.g. "insufficient_quota")
  double retry_delay_ms = -1.0;  // a delay the body asks for (Gemini's RetryInfo); -1 if none
};

WireRequest build_request(const ModelSpec& spec, const GenerationParams& params,
                          std::span<const ChatMessage> messages);
/// The authentication and content headers (the key goes only here).
std::vector<std::pair<std::string, std::string>> request_headers(const ModelSpec& spec, const ApiKey& key);
/// @throws mtg::Error ("malformed response: ...") when the body is not the provider's answer.
ModelAnswer parse_answer(const ModelSpec& spec, const std::string& body);
ErrorInfo parse_error(const ModelSpec& spec, const std::string& body);

/// The system messages joined (Anthropic and Gemini take the system prompt as its own field).
std::string system_text(std::span<const ChatMessage> messages);

// Per provider (wire_<provider>.cc).
namespace openai {
WireRequest build_request(const ModelSpec& spec, const GenerationParams& params, std::span<const ChatMessage> messages);
ModelAnswer parse_answer(const std::string& body);
}  // namespace openai
namespace anthropic {
WireRequest build_request(const ModelSpec& spec, const GenerationParams& params, std::span<const ChatMessage> messages);
ModelAnswer parse_answer(const std::string& body);
}  // namespace anthropic
namespace gemini {
WireRequest build_request(const ModelSpec& spec, const GenerationParams& params, std::span<const ChatMessage> messages);
ModelAnswer parse_answer(const std::string& body);
}  // namespace gemini

}  // namespace mtg::vlm
