#include "agents/vlm/model_spec.h"

#include <cctype>
#include <cstdlib>

#include "core/util/error.h"

namespace mtg::vlm {
namespace {

constexpr std::string_view kCompatible = "openai-compatible:";

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::string(v) : fallback;
}

std::string strip_slash(std::string url) {
  while (!url.empty() && url.back() == '/') url.pop_back();
  return url;
}

// "<scheme>://<host>[:<port>][/<path>]:<model>": the URL ends at the first ':' after the host
// that is not followed by a port number.
std::pair<std::string, std::string> split_url_model(std::string_view rest, std::string_view spec) {
  const auto scheme = rest.find("://");
  if (scheme == std::string_view::npos) {
    throw Error("agent '" + std::string(spec) + "': expected openai-compatible:<http(s)://host[:port][/path]>:<model>");
  }
  std::size_t i = scheme + 3;
  while (i < rest.size() && rest[i] != ':' && rest[i] != '/') ++i;  // host
  if (i < rest.size() && rest[i] == ':') {
    std::size_t j = i + 1;
    while (j < rest.size() && std::isdigit(static_cast<unsigned char>(rest[j])) != 0) ++j;
    if (j > i + 1 && (j == rest.size() || rest[j] == '/' || rest[j] == ':')) i = j;  // a port
  }
  while (i < rest.size() && rest[i] != ':') ++i;  // path
  if (i + 1 >= rest.size()) throw Error("agent '" + std::string(spec) + "': no model after the URL");
  return {std::string(rest.substr(0, i)), std::string(rest.substr(i + 1))};
}

}  // namespace

std::string ModelSpec::provider_name() const {
  switch (provider) {
    case Provider::kOpenAi: return "openai";
    case Provider::kAnthropic: return "anthropic";
    case Provider::kGemini: return "gemini";
    case Provider::kOpenAiCompatible: return "openai-compatible";
  }
  return "?";
}

std::string ModelSpec::spec() const {
  if (provider == Provider::kOpenAiCompatible) return provider_name() + ":" + base_url + ":" + model;
  return provider_name() + ":" + model;
}

std::string ModelSpec::bucket() const { return provider_name() + ":" + model; }

bool is_model_spec(std::string_view spec) {
  for (const std::string_view p : {"openai:", "anthropic:", "gemini:", "openai-compatible:"}) {
    if (spec.substr(0, p.size()) == p) return true;
  }
  return false;
}

ModelSpec parse_model_spec(std::string_view spec, const std::string& base_url_override) {
  ModelSpec m;
  std::string default_url;
  std::string_view rest;
  if (spec.substr(0, kCompatible.size()) == kCompatible) {
    m.provider = Provider::kOpenAiCompatible;
    auto [url, model] = split_url_model(spec.substr(kCompatible.size()), spec);
    default_url = url;
    m.model = model;
  } else {
    const auto colon = spec.find(':');
    const std::string_view name = spec.substr(0, colon);
    if (name == "openai") {
      m.provider = Provider::kOpenAi;
      default_url = env_or("OPENAI_BASE_URL", "https://api.openai.com/v1");
    } else if (name == "anthropic") {
      m.provider = Provider::kAnthropic;
      default_url = env_or("ANTHROPIC_BASE_URL", "https://api.anthropic.com");
    } else if (name == "gemini") {
      m.provider = Provider::kGemini;
      default_url = env_or("GEMINI_BASE_URL", "https://generativelanguage.googleapis.com");
    } else {
      throw Error("agent '" + std::string(spec) +
                  "': unknown provider (openai:, anthropic:, gemini:, openai-compatible:<url>:)");
    }
    m.model = colon == std::string_view::npos ? "" : std::string(spec.substr(colon + 1));
  }
  if (m.model.empty()) throw Error("agent '" + std::string(spec) + "': no model name");
  m.base_url = strip_slash(base_url_override.empty() ? default_url : base_url_override);
  return m;
}

std::string api_key_variable(Provider provider) {
  switch (provider) {
    case Provider::kOpenAi: return "OPENAI_API_KEY";
    case Provider::kAnthropic: return "ANTHROPIC_API_KEY";
    case Provider::kGemini: return "GEMINI_API_KEY";
    case Provider::kOpenAiCompatible: return "OPENAI_COMPATIBLE_API_KEY";
  }
  return "";
}

}  // namespace mtg::vlm
