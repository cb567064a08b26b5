#include "agents/vlm/model_client.h"

#include <chrono>

#include "agents/vlm/http_client.h"
#include "agents/vlm/retry_policy.h"
#include "agents/vlm/wire.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/log.h"

namespace mtg::vlm {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

}  // namespace

ModelClient::ModelClient(ModelSpec spec, ApiKey key, const VlmSettings& settings, PriceTable prices,
                         ResponseCache* cache, RateGate* gate)
    : spec_(std::move(spec)), key_(std::move(key)), settings_(settings), prices_(std::move(prices)), cache_(cache),
      gate_(gate) {
  params_.temperature = settings.temperature;
  params_.max_output_tokens = settings.max_output_tokens;
  params_.image_detail = settings.image_detail;
  if (settings.seed >= 0) params_.seed = settings.seed;
}

void ModelClient::cancel() {
  cancelled_ = true;
  wake_.notify_all();
}

bool ModelClient::sleep_ms(double ms) {
  std::unique_lock lock(mutex_);
  wake_.wait_for(lock, std::chrono::duration<double, std::milli>(ms), [this] { return cancelled_.load(); });
  return !cancelled_;
}

int ModelClient::estimate_tokens(std::span<const ChatMessage> messages) const {
  // About 4 characters per token; an image as OpenAI counts a low-detail one (85) or a
  // 512-px-tiled high-detail one (765). The governor corrects the estimate after the call.
  std::size_t chars = 0, images = 0;
  for (const ChatMessage& m : messages) {
    chars += m.text.size();
    images += m.images.size();
  }
  const int per_image = params_.image_detail == "low" ? 85 : 765;
  return static_cast<int>(chars / 4 + images * per_image) + params_.max_output_tokens;
}

CallResult ModelClient::stopped_result() {
  CallResult r;
  std::lock_guard lock(mutex_);
  r.error = cancelled_ ? "the adapter is shutting down" : stop_reason_;
  r.stop_agent = !stop_reason_.empty();
  return r;
}

CallResult ModelClient::call(std::span<const ChatMessage> messages) {
  const auto started = Clock::now();
  bool stopped = false;
  {
    std::lock_guard lock(mutex_);
    stopped = !stop_reason_.empty() || cancelled_;
  }
  if (stopped) return stopped_result();
  const WireRequest wire = build_request(spec_, params_, messages);
  const std::string key = cache_key(wire.url, wire.body);
  CallResult r;
  for (const ChatMessage& m : messages) r.images += static_cast<int>(m.images.size());
  auto finish = [&](const ModelAnswer& a) {
    r.ok = true;
    r.text = a.text;
    r.input_tokens = a.input_tokens;
    r.output_tokens = a.output_tokens;
    r.cost_usd = prices_.cost_usd(spec_.bucket(), a.input_tokens, a.output_tokens);
    r.latency_ms = ms_since(started);
    return r;
  };
  if (cache_ != nullptr) {
    if (const auto hit = cache_->get(key)) {
      r.cache_hit = true;
      return finish(*hit);
    }
    if (settings_.cache_only) {
      r.error = "cache miss with --cache-only: " + spec_.spec() + " request " + key.substr(0, 12) + " is not in " +
                cache_->file().string();
      r.latency_ms = ms_since(started);
      return r;
    }
  }

  HttpRequest http{wire.url, request_headers(spec_, key_), wire.body, settings_.request_timeout_s,
                   settings_.connect_timeout_s};
  const int estimate = estimate_tokens(messages);
  const std::uint64_t jitter_seed = fnv1a64(key);
  const Backoff backoff{settings_.backoff_base_s, settings_.backoff_cap_s};
  std::string last_error;
  for (int attempt = 0; attempt < settings_.max_attempts; ++attempt) {
    const std::int64_t permit = gate_ != nullptr ? gate_->acquire(spec_.bucket(), estimate) : 0;
    if (cancelled_) return stopped_result();
    const HttpResponse resp = http_post(http, &cancelled_);
    ++r.http_attempts;
    Classified c = classify(spec_, resp);
    if (c.outcome == Outcome::kSuccess) {
      try {
        const ModelAnswer a = parse_answer(spec_, resp.body);
        if (gate_ != nullptr) gate_->done(spec_.bucket(), permit, a.input_tokens + a.output_tokens);
        if (cache_ != nullptr) cache_->put(key, spec_.bucket(), a);
        return finish(a);
      } catch (const Error& e) {
        // A cut or garbled body: the next attempt may well be whole.
        c.outcome = Outcome::kRetry;
        c.message = std::string(e.what()) + " (HTTP " + std::to_string(resp.status) + ")";
      }
    }
    if (gate_ != nullptr) gate_->done(spec_.bucket(), permit, estimate);
    if (cancelled_) return stopped_result();
    last_error = key_.redact(c.message);
    if (c.outcome == Outcome::kStopAgent) {
      std::lock_guard lock(mutex_);
      if (stop_reason_.empty()) stop_reason_ = spec_.spec() + ": " + last_error;
      r.error = stop_reason_;
      r.stop_agent = true;
      r.latency_ms = ms_since(started);
      return r;
    }
    if (c.outcome == Outcome::kFailCall || attempt + 1 == settings_.max_attempts) break;
    const double wait = retry_delay_ms(c, attempt, backoff, jitter_seed);
    if (wait > settings_.max_retry_wait_s * 1000.0) {
      last_error += " (the server asks to wait " + std::to_string(static_cast<int>(wait / 1000)) + " s)";
      break;
    }
    if (resp.status == 429 && gate_ != nullptr && c.server_delay_ms >= 0) gate_->pause(spec_.bucket(), wait);
    log::warn(spec_.spec() + ": " + last_error + "; retry " + std::to_string(attempt + 1) + " in " +
              std::to_string(static_cast<int>(wait)) + " ms");
    if (!sleep_ms(wait)) return stopped_result();
  }
  r.error = spec_.spec() + ": " + last_error + " (after " + std::to_string(r.http_attempts) + " attempt" +
            (r.http_attempts == 1 ? "" : "s") + ")";
  r.latency_ms = ms_since(started);
  return r;
}

}  // namespace mtg::vlm
