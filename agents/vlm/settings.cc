#include "agents/vlm/settings.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/util/error.h"

namespace mtg::vlm {
namespace {

namespace fs = std::filesystem;

template <typename T>
void take(const nlohmann::json& j, const char* key, T& field, const std::string& origin) {
  if (!j.contains(key)) return;
  try {
    field = j.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw Error(origin + ": field '" + key + "' has the wrong type");
  }
}

}  // namespace

VlmSettings VlmSettings::from_json_file(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw Error(file + ": cannot open the model settings file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw Error(file + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  if (!j.is_object()) throw Error(file + ": expected a JSON object");
  VlmSettings s;
  static const char* const kFields[] = {
      "temperature", "max_output_tokens", "seed", "image_roles", "image_detail", "image_max_side", "history_steps",
      "history_images", "request_timeout_s", "connect_timeout_s", "max_attempts", "backoff_base_s", "backoff_cap_s",
      "max_retry_wait_s", "rpm", "tpm", "rate_window_s", "cache_file", "cache_only", "no_cache", "prompts_dir",
      "prices_file", "key_file", "base_url", "workers"};
  for (const auto& [key, value] : j.items()) {
    bool ok = false;
    for (const char* f : kFields) ok = ok || key == f;
    if (!ok) throw Error(file + ": unknown field '" + key + "'");
  }
  take(j, "temperature", s.temperature, file);
  take(j, "max_output_tokens", s.max_output_tokens, file);
  take(j, "seed", s.seed, file);
  take(j, "image_roles", s.image_roles, file);
  take(j, "image_detail", s.image_detail, file);
  take(j, "image_max_side", s.image_max_side, file);
  take(j, "history_steps", s.history_steps, file);
  take(j, "history_images", s.history_images, file);
  take(j, "request_timeout_s", s.request_timeout_s, file);
  take(j, "connect_timeout_s", s.connect_timeout_s, file);
  take(j, "max_attempts", s.max_attempts, file);
  take(j, "backoff_base_s", s.backoff_base_s, file);
  take(j, "backoff_cap_s", s.backoff_cap_s, file);
  take(j, "max_retry_wait_s", s.max_retry_wait_s, file);
  take(j, "rpm", s.rpm, file);
  take(j, "tpm", s.tpm, file);
  take(j, "rate_window_s", s.rate_window_s, file);
  take(j, "cache_file", s.cache_file, file);
  take(j, "cache_only", s.cache_only, file);
  take(j, "no_cache", s.no_cache, file);
  take(j, "prompts_dir", s.prompts_dir, file);
  take(j, "prices_file", s.prices_file, file);
  take(j, "key_file", s.key_file, file);
  take(j, "base_url", s.base_url, file);
  take(j, "workers", s.workers, file);
  try {
    s.validate();
  } catch (const Error& e) {
    throw Error(file + ": " + e.what());
  }
  return s;
}

void VlmSettings::validate() const {
  auto fail = [](const std::string& what) { throw Error(what); };
  if (temperature < 0.0 || temperature > 2.0) fail("temperature must be in [0, 2]");
  if (max_output_tokens < 1) fail("max_output_tokens must be at least 1");
  if (image_detail != "low" && image_detail != "high" && image_detail != "auto") {
    fail("image_detail must be low, high or auto");
  }
  if (image_max_side < 0 || history_steps < 0 || history_images < 0) {
    fail("image_max_side, history_steps and history_images must not be negative");
  }
  if (request_timeout_s <= 0.0 || connect_timeout_s <= 0.0) fail("time-outs must be positive");
  if (max_attempts < 1) fail("max_attempts must be at least 1");
  if (backoff_base_s < 0.0 || backoff_cap_s < backoff_base_s) fail("need 0 <= backoff_base_s <= backoff_cap_s");
  if (rpm < 0 || tpm < 0) fail("rpm and tpm must not be negative");
  if (rate_window_s <= 0.0) fail("rate_window_s must be positive");
  if (cache_only && no_cache) fail("cache_only and no_cache exclude each other");
  if (workers < 1) fail("workers must be at least 1");
}

std::string VlmSettings::resolved_cache_file() const {
  if (!cache_file.empty()) return cache_file;
  if (const char* dir = std::getenv("MTG_CACHE_DIR"); dir != nullptr && *dir != '\0') {
    return (fs::path(dir) / "vlm-cache.sqlite").string();
  }
  const char* home = std::getenv("HOME");
  return (fs::path(home != nullptr ? home : ".") / ".cache" / "mtg" / "vlm-cache.sqlite").string();
}

}  // namespace mtg::vlm
