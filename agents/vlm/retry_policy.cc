#include "agents/vlm/retry_policy.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <ctime>

#include "agents/vlm/wire.h"
#include "core/util/rng.h"

namespace mtg::vlm {
namespace {

bool contains(const std::string& haystack, const char* needle) {
  std::string h = haystack;
  std::transform(h.begin(), h.end(), h.begin(), [](unsigned char c) { return std::tolower(c); });
  return h.find(needle) != std::string::npos;
}

// "6m0s", "1.5s", "20ms", "1h2m" (OpenAI's reset headers).
double go_duration_ms(const std::string& s) {
  double total = 0.0;
  std::size_t i = 0;
  bool any = false;
  while (i < s.size()) {
    std::size_t j = i;
    while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) != 0 || s[j] == '.')) ++j;
    if (j == i) return -1.0;
    const double v = std::stod(s.substr(i, j - i));
    std::size_t k = j;
    while (k < s.size() && std::isalpha(static_cast<unsigned char>(s[k])) != 0) ++k;
    const std::string unit = s.substr(j, k - j);
    if (unit == "h") total += v * 3600e3;
    else if (unit == "m") total += v * 60e3;
    else if (unit == "s" || unit.empty()) total += v * 1e3;
    else if (unit == "ms") total += v;
    else return -1.0;
    any = true;
    i = k;
  }
  return any ? total : -1.0;
}

// Seconds from now until an absolute time (the reset headers name one); wall clock, used only
// to decide how long to sleep.
double until_ms(std::time_t when) {
  const double delta = std::difftime(when, std::time(nullptr)) * 1000.0;
  return std::max(0.0, delta);
}

double http_date_ms(const std::string& s) {
  std::tm tm{};
  if (strptime(s.c_str(), "%a, %d %b %Y %H:%M:%S", &tm) == nullptr) return -1.0;
  return until_ms(timegm(&tm));
}

double rfc3339_ms(const std::string& s) {
  std::tm tm{};
  if (strptime(s.c_str(), "%Y-%m-%dT%H:%M:%S", &tm) == nullptr) return -1.0;
  return until_ms(timegm(&tm));
}

double number_or(const std::string& s, double fallback) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    return used == s.size() ? v : fallback;
  } catch (const std::exception&) {
    return fallback;
  }
}

}  // namespace

double header_delay_ms(const HttpResponse& r) {
  auto get = [&](const char* name) -> std::string {
    const auto it = r.headers.find(name);
    return it == r.headers.end() ? "" : it->second;
  };
  if (const std::string v = get("retry-after-ms"); !v.empty()) {
    if (const double ms = number_or(v, -1.0); ms >= 0) return ms;
  }
  if (const std::string v = get("retry-after"); !v.empty()) {
    const double s = number_or(v, -1.0);
    return s >= 0 ? s * 1000.0 : http_date_ms(v);
  }
  double reset = -1.0;
  for (const char* name : {"x-ratelimit-reset-requests", "x-ratelimit-reset-tokens"}) {
    if (const std::string v = get(name); !v.empty()) reset = std::max(reset, go_duration_ms(v));
  }
  for (const char* name : {"anthropic-ratelimit-requests-reset", "anthropic-ratelimit-tokens-reset"}) {
    if (const std::string v = get(name); !v.empty()) reset = std::max(reset, rfc3339_ms(v));
  }
  return reset;
}

Classified classify(const ModelSpec& spec, const HttpResponse& r) {
  Classified c;
  if (!r.transport_error.empty()) {
    c.outcome = Outcome::kRetry;
    c.message = "network error: " + r.transport_error;
    return c;
  }
  if (r.status >= 200 && r.status < 300) return c;
  const ErrorInfo info = parse_error(spec, r.body);
  const std::string what = "HTTP " + std::to_string(r.status) + " from " + spec.provider_name() +
                           (info.message.empty() ? "" : ": " + info.message);
  c.message = what;
  c.server_delay_ms = std::max(header_delay_ms(r), info.retry_delay_ms);
  const std::string text = info.code + " " + info.message;
  const bool quota = contains(text, "insufficient_quota") || contains(text, "billing") ||
                     contains(text, "credit balance") || contains(text, "exceeded your current quota");
  if (r.status == 401 || r.status == 403) {
    c.outcome = Outcome::kStopAgent;
    c.message = "authentication failed (" + what + ")";
  } else if (r.status == 402 || quota) {
    c.outcome = Outcome::kStopAgent;
    c.message = "quota or billing exhausted (" + what + ")";
  } else if (r.status == 404) {
    c.outcome = Outcome::kStopAgent;
    c.message = "model or endpoint not found (" + what + ")";
  } else if (r.status == 408 || r.status == 409 || r.status == 425 || r.status == 429 || r.status >= 500) {
    c.outcome = Outcome::kRetry;  // includes Anthropic's 529 "overloaded"
  } else {
    c.outcome = Outcome::kFailCall;
  }
  return c;
}

double retry_delay_ms(const Classified& c, int retry, const Backoff& backoff, std::uint64_t jitter_seed) {
  Rng rng(derive_seed(jitter_seed, static_cast<std::uint64_t>(retry)));
  const double u = rng.uniform01();
  if (c.server_delay_ms >= 0.0) return c.server_delay_ms * (1.0 + 0.1 * u);
  const double full = std::min(backoff.cap_s, backoff.base_s * static_cast<double>(1ull << std::min(retry, 30)));
  return 1000.0 * full * (0.5 + 0.5 * u);
}

}  // namespace mtg::vlm
