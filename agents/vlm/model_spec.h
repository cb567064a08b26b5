#pragma once
// Which model an agent spec names, and where its API lives:
//   openai:<model>                      api.openai.com (OPENAI_BASE_URL overrides)
//   anthropic:<model>                   api.anthropic.com (ANTHROPIC_BASE_URL overrides)
//   gemini:<model>                      generativelanguage.googleapis.com (GEMINI_BASE_URL overrides)
//   openai-compatible:<url>:<model>     any chat-completions server (vLLM, Ollama, llama.cpp, OpenRouter)
// The model may itself contain ':' (Ollama's "llava:13b").

#include <optional>
#include <string>
#include <string_view>

namespace mtg::vlm {

enum class Provider { kOpenAi, kAnthropic, kGemini, kOpenAiCompatible };

struct ModelSpec {
  Provider provider = Provider::kOpenAi;
  std::string model;
  std::string base_url;  // without a trailing '/'

  /// "openai", "anthropic", "gemini" or "openai-compatible".
  std::string provider_name() const;
  /// The agent spec this was parsed from (round trip of parse_model_spec).
  std::string spec() const;
  /// The rate-limit and price bucket, "<provider>:<model>".
  std::string bucket() const;
};

/// Whether `spec` names a model adapter (rather than a built-in agent).
bool is_model_spec(std::string_view spec);

/// @param base_url_override used instead of the provider's default (and of the environment).
/// @throws mtg::Error naming the spec when it is malformed.
ModelSpec parse_model_spec(std::string_view spec, const std::string& base_url_override = "");

/// The environment variable holding the provider's API key ("OPENAI_API_KEY", ...).
std::string api_key_variable(Provider provider);

}  // namespace mtg::vlm
