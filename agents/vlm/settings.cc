#include "agents/vlm/settings.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/util/error.h"

namespace mtg::vlm {
namespace {

namespace fs = std::filesystem;

// Reads the fields it is asked for and remembers their names, so that whatever else the file
// holds can be reported as unknown.
class Fields {
 public:
  Fields(const nlohmann::json& j, std::string origin) : j_(j), origin_(std::move(origin)) {}
  template <typename T>
  void take(const char* key, T& field) {
    known_.insert(key);
    if (!j_.contains(key)) return;
    try {
      field = j_.at(key).get<T>();
    } catch (const nlohmann::json::exception&) {
      throw Error(origin_ + ": field '" + key + "' has the wrong type");
    }
  }
  void reject_unknown() const {
    for (const auto& [key, value] : j_.items()) {
      if (known_.count(key) == 0) throw Error(origin_ + ": unknown field '" + key + "'");
    }
  }

 private:
  const nlohmann::json& j_;
  std::string origin_;
  std::set<std::string> known_;
};

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
  Fields f(j, file);
  f.take("temperature", s.temperature);
  f.take("max_output_tokens", s.max_output_tokens);
  f.take("seed", s.seed);
  f.take("image_roles", s.image_roles);
  f.take("image_detail", s.image_detail);
  f.take("image_max_side", s.image_max_side);
  f.take("history_steps", s.history_steps);
  f.take("history_images", s.history_images);
  f.take("request_timeout_s", s.request_timeout_s);
  f.take("connect_timeout_s", s.connect_timeout_s);
  f.take("max_attempts", s.max_attempts);
  f.take("backoff_base_s", s.backoff_base_s);
  f.take("backoff_cap_s", s.backoff_cap_s);
  f.take("max_retry_wait_s", s.max_retry_wait_s);
  f.take("rpm", s.rpm);
  f.take("tpm", s.tpm);
  f.take("rate_window_s", s.rate_window_s);
  f.take("cache_file", s.cache_file);
  f.take("cache_only", s.cache_only);
  f.take("no_cache", s.no_cache);
  f.take("prompts_dir", s.prompts_dir);
  f.take("prices_file", s.prices_file);
  f.take("key_file", s.key_file);
  f.take("base_url", s.base_url);
  f.take("workers", s.workers);
  f.reject_unknown();
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

nlohmann::json VlmSettings::provenance_json() const {
  return {{"temperature", temperature},
          {"max_output_tokens", max_output_tokens},
          {"seed", seed},
          {"image_roles", image_roles},
          {"image_detail", image_detail},
          {"image_max_side", image_max_side},
          {"history_steps", history_steps},
          {"history_images", history_images},
          {"prompts_dir", prompts_dir.empty() ? "shipped" : prompts_dir},
          {"prices_file", prices_file.empty() ? "shipped" : prices_file},
          {"base_url", base_url.empty() ? "provider default" : base_url},
          {"cache_only", cache_only},
          {"no_cache", no_cache}};
}

}  // namespace mtg::vlm
