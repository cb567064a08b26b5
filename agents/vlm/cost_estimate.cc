#include "agents/vlm/cost_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace mtg::vlm {
namespace {

struct Figures {
  std::int64_t calls = 0;
  std::int64_t images = 0;
  std::int64_t input_tokens = 0;
  std::int64_t output_tokens = 0;
  double cost_usd = 0.0;

  void add(const Figures& o) {
    calls += o.calls;
    images += o.images;
    input_tokens += o.input_tokens;
    output_tokens += o.output_tokens;
    cost_usd += o.cost_usd;
  }
};

Figures halfway(const Figures& a, const Figures& b) {
  auto mid = [](std::int64_t x, std::int64_t y) { return (x + y + 1) / 2; };
  return {mid(a.calls, b.calls), mid(a.images, b.images), mid(a.input_tokens, b.input_tokens),
          mid(a.output_tokens, b.output_tokens), (a.cost_usd + b.cost_usd) / 2.0};
}

Figures episode_figures(std::int64_t system_chars, const std::vector<StepPrompt>& steps, const VlmSettings& s,
                        int per_image) {
  Figures f;
  for (const CallSize& c : call_sizes(system_chars, steps, s.history_steps, s.history_images)) {
    ++f.calls;
    f.images += c.images;
    f.input_tokens += text_tokens(c.chars) + static_cast<std::int64_t>(per_image) * c.images;
  }
  // Answers are a key or a short sentence; what a call may cost is what it may answer.
  f.output_tokens = f.calls * s.max_output_tokens;
  return f;
}

double cost_of(const Figures& f, const Price* price) {
  if (price == nullptr) return 0.0;
  return (price->input_per_mtok * static_cast<double>(f.input_tokens) +
          price->output_per_mtok * static_cast<double>(f.output_tokens)) / 1e6;
}

// Hours the rate limits allow the calls to take: the window times however many windows the
// calls or their tokens fill (output counted at its most, as the gate's permit counts it).
nlohmann::json hours_of(const Figures& f, const VlmSettings& s) {
  if (s.rpm <= 0 && s.tpm <= 0) return nullptr;
  double windows = 0.0;
  if (s.rpm > 0) windows = std::max(windows, static_cast<double>(f.calls) / s.rpm);
  if (s.tpm > 0) windows = std::max(windows, static_cast<double>(f.input_tokens + f.output_tokens) / s.tpm);
  return windows * s.rate_window_s / 3600.0;
}

nlohmann::json figures_json(const Figures& f, const nlohmann::json& hours) {
  return {{"calls", f.calls},
          {"images", f.images},
          {"input_tokens", f.input_tokens},
          {"output_tokens", f.output_tokens},
          {"cost_usd", f.cost_usd},
          {"hours", hours}};
}

std::string image_rule(Provider provider, const std::string& detail) {
  switch (provider) {
    case Provider::kAnthropic: return "Anthropic: width x height / 750, the longer side brought down to 1568 px";
    case Provider::kGemini: return "Gemini: 258 up to 384 x 384 px, else 258 per 768-px tile";
    case Provider::kOpenAi:
    case Provider::kOpenAiCompatible: break;
  }
  if (detail == "low") return "OpenAI, low detail: 85 per image";
  return "OpenAI, " + detail + " detail: 85 + 170 per 512-px tile (fitted in 2048 px, shorter side at most 768)";
}

const char* const kScenarios[] = {"low", "expected", "high"};

std::string grouped(std::int64_t n) {
  std::string digits = std::to_string(n < 0 ? -n : n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return n < 0 ? "-" + out : out;
}

std::string usd(double x) {
  char buf[48];
  std::snprintf(buf, sizeof buf, x >= 100.0 ? "$%.0f" : x >= 1.0 ? "$%.2f" : "$%.4f", x);
  return buf;
}

std::string hours_text(const nlohmann::json& h) {
  if (h.is_null()) return "-";
  char buf[32];
  const double v = h.get<double>();
  if (v < 0.01) return "<0.01";
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

std::string row(const std::string& label, const nlohmann::json& f) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "    %-20s %10s %9s %14s %14s %11s %8s\n", label.c_str(),
                grouped(f["calls"].get<std::int64_t>()).c_str(), grouped(f["images"].get<std::int64_t>()).c_str(),
                grouped(f["input_tokens"].get<std::int64_t>()).c_str(),
                grouped(f["output_tokens"].get<std::int64_t>()).c_str(), usd(f["cost_usd"].get<double>()).c_str(),
                hours_text(f["hours"]).c_str());
  return buf;
}

std::string block(const nlohmann::json& scenarios) {
  char head[256];
  std::snprintf(head, sizeof head, "    %-20s %10s %9s %14s %14s %11s %8s\n", "", "calls", "images", "input tokens",
                "output (most)", "list price", "hours");
  return head + row("solves it (low)", scenarios["low"]) + row("expected", scenarios["expected"]) +
         row("never ends (high)", scenarios["high"]);
}

}  // namespace

std::pair<int, int> sent_image_size(int width, int height, int max_side) {
  const int longest = std::max(width, height);
  if (max_side <= 0 || longest <= max_side) return {width, height};
  // As cv::resize rounds the scaled size (images_to_send).
  const double f = static_cast<double>(max_side) / longest;
  return {std::max(1, static_cast<int>(std::lround(width * f))), std::max(1, static_cast<int>(std::lround(height * f)))};
}

int image_tokens(Provider provider, const std::string& detail, int width, int height) {
  if (width <= 0 || height <= 0) return 0;
  double w = width, h = height;
  auto scale = [&](double f) {
    w = std::round(w * f);
    h = std::round(h * f);
  };
  switch (provider) {
    case Provider::kAnthropic: {
      if (std::max(w, h) > 1568.0) scale(1568.0 / std::max(w, h));
      return static_cast<int>(std::ceil(w * h / 750.0));
    }
    case Provider::kGemini: {
      if (w <= 384.0 && h <= 384.0) return 258;
      return 258 * static_cast<int>(std::ceil(w / 768.0) * std::ceil(h / 768.0));
    }
    case Provider::kOpenAi:
    case Provider::kOpenAiCompatible: {
      if (detail == "low") return 85;
      // "auto" lets the provider choose: counted as high, the dearer of the two.
      if (std::max(w, h) > 2048.0) scale(2048.0 / std::max(w, h));
      if (std::min(w, h) > 768.0) scale(768.0 / std::min(w, h));
      return 85 + 170 * static_cast<int>(std::ceil(w / 512.0) * std::ceil(h / 512.0));
    }
  }
  return 0;
}

std::vector<CallSize> call_sizes(std::int64_t system_chars, const std::vector<StepPrompt>& steps, int history_steps,
                                 int history_images) {
  std::vector<CallSize> out;
  out.reserve(steps.size());
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const std::size_t kept = history_steps == 0 ? k : std::min<std::size_t>(k, static_cast<std::size_t>(history_steps));
    CallSize c;
    c.chars = system_chars;
    for (std::size_t j = k - kept; j <= k; ++j) {
      c.chars += steps[j].user_chars + (j < k ? steps[j].reply_chars : 0);
      if (k - j < static_cast<std::size_t>(std::max(0, history_images))) c.images += steps[j].images;
    }
    out.push_back(c);
  }
  return out;
}

std::vector<StepPrompt> never_ending_steps(const EpisodePrompts& prompts) {
  std::vector<StepPrompt> out = prompts.solved;
  if (out.empty()) return out;
  const std::size_t from = out.size() > 1 ? 1 : 0;
  const auto n = static_cast<std::int64_t>(out.size() - from);
  std::int64_t user = 0, reply = 0, images = 0;
  for (std::size_t i = from; i < out.size(); ++i) {
    user += out[i].user_chars;
    reply += out[i].reply_chars;
    images += out[i].images;
  }
  const StepPrompt mean{(user + n / 2) / n, (reply + n / 2) / n, static_cast<int>((images + n / 2) / n)};
  const std::size_t limit = std::max<std::size_t>(out.size(), static_cast<std::size_t>(std::max(0, prompts.step_limit)));
  out.resize(limit, mean);
  return out;
}

nlohmann::json estimate_run(const EstimateInput& in) {
  const VlmSettings& s = in.settings;
  const auto [sent_w, sent_h] = sent_image_size(in.image_width, in.image_height, s.image_max_side);
  struct Agent {
    std::int64_t episodes = 0;
    Provider provider = Provider::kOpenAi;
    std::string bucket;
    int per_image = 0;
    Figures low, high;
  };
  std::map<std::string, Agent> agents;
  for (const EpisodeToEstimate& e : in.episodes) {
    const auto [it, fresh] = agents.try_emplace(e.agent);
    Agent& a = it->second;
    if (fresh) {
      const ModelSpec spec = parse_model_spec(e.agent, s.base_url);
      a.provider = spec.provider;
      a.bucket = spec.bucket();
      a.per_image = in.images ? image_tokens(spec.provider, s.image_detail, sent_w, sent_h) : 0;
    }
    ++a.episodes;
    a.low.add(episode_figures(e.prompts.system_chars, e.prompts.solved, s, a.per_image));
    a.high.add(episode_figures(e.prompts.system_chars, never_ending_steps(e.prompts), s, a.per_image));
  }

  nlohmann::json out = {{"episodes", static_cast<std::int64_t>(in.episodes.size())},
                        {"not_estimated", in.not_estimated},
                        {"not_estimated_why", in.not_estimated_why},
                        {"stand_ins", in.stand_ins},
                        {"prompt_version", in.prompt_version},
                        {"images", in.images},
                        {"image_width", in.image_width},
                        {"image_height", in.image_height},
                        {"sent_width", sent_w},
                        {"sent_height", sent_h},
                        {"image_detail", s.image_detail},
                        {"history_steps", s.history_steps},
                        {"history_images", s.history_images},
                        {"max_output_tokens", s.max_output_tokens},
                        {"rpm", s.rpm},
                        {"tpm", s.tpm},
                        {"rate_window_s", s.rate_window_s},
                        {"agents", nlohmann::json::object()}};
  Figures total[3];
  nlohmann::json total_hours[3] = {nullptr, nullptr, nullptr};
  for (auto& [spec, a] : agents) {
    const Price* price = in.prices.find(a.bucket);
    a.low.cost_usd = cost_of(a.low, price);
    a.high.cost_usd = cost_of(a.high, price);
    const Figures figures[3] = {a.low, halfway(a.low, a.high), a.high};
    nlohmann::json j = {{"episodes", a.episodes},
                        {"bucket", a.bucket},
                        {"price_known", price != nullptr},
                        {"input_per_mtok", price != nullptr ? price->input_per_mtok : 0.0},
                        {"output_per_mtok", price != nullptr ? price->output_per_mtok : 0.0},
                        {"image_tokens", a.per_image},
                        {"image_rule", in.images ? image_rule(a.provider, s.image_detail) : "no images (text only)"},
                        {"expected_episode_cost_usd", figures[1].cost_usd / static_cast<double>(a.episodes)}};
    for (int i = 0; i < 3; ++i) {
      // Each agent's calls go to its own bucket, and the buckets are served side by side: the
      // run takes as long as its slowest agent.
      const nlohmann::json hours = hours_of(figures[i], s);
      j[kScenarios[i]] = figures_json(figures[i], hours);
      total[i].add(figures[i]);
      if (!hours.is_null() && (total_hours[i].is_null() || hours.get<double>() > total_hours[i].get<double>())) {
        total_hours[i] = hours;
      }
    }
    out["agents"][spec] = std::move(j);
  }
  out["total"] = nlohmann::json::object();
  for (int i = 0; i < 3; ++i) out["total"][kScenarios[i]] = figures_json(total[i], total_hours[i]);
  return out;
}

std::string estimate_text(const nlohmann::json& e) {
  std::string out;
  char line[512];
  const bool images = e.value("images", false);
  std::string history = e["history_steps"].get<int>() == 0
                            ? std::string("the whole episode")
                            : "the last " + std::to_string(e["history_steps"].get<int>()) + " step(s)";
  if (images) history += ", images of the newest " + std::to_string(e["history_images"].get<int>()) + " step(s)";
  std::snprintf(line, sizeof line, "cost before spending: %s episode(s) of %zu model agent(s); prompts %s; %s; history: %s\n",
                grouped(e["episodes"].get<std::int64_t>()).c_str(), e["agents"].size(),
                e["prompt_version"].get<std::string>().c_str(),
                images ? ("images " + std::to_string(e["image_width"].get<int>()) + "x" +
                          std::to_string(e["image_height"].get<int>()) + " sent at " +
                          std::to_string(e["sent_width"].get<int>()) + "x" + std::to_string(e["sent_height"].get<int>()))
                             .c_str()
                       : "text only",
                history.c_str());
  out += line;
  for (const auto& [spec, a] : e["agents"].items()) {
    const std::string price =
        a["price_known"].get<bool>()
            ? usd(a["input_per_mtok"].get<double>()) + " in / " + usd(a["output_per_mtok"].get<double>()) +
                  " out per million tokens"
            : "no price in the table (counted as $0)";
    std::snprintf(line, sizeof line, "  %s: %s episode(s), %s; %d tokens per image (%s)\n", spec.c_str(),
                  grouped(a["episodes"].get<std::int64_t>()).c_str(), price.c_str(), a["image_tokens"].get<int>(),
                  a["image_rule"].get<std::string>().c_str());
    out += line;
    out += block(a);
  }
  if (e["agents"].size() > 1) {
    out += "  all agents:\n";
    out += block(e["total"]);
  }
  if (e["rpm"].get<int>() <= 0 && e["tpm"].get<int>() <= 0) {
    out += "  hours: no rate limit set (--rpm, --tpm): as fast as the providers answer at --parallel\n";
  } else {
    std::snprintf(line, sizeof line, "  hours: at --rpm %d --tpm %d per %g s window, each agent's calls in its own bucket\n",
                  e["rpm"].get<int>(), e["tpm"].get<int>(), e["rate_window_s"].get<double>());
    out += line;
  }
  std::snprintf(line, sizeof line,
                "  approximated: text at 4 characters a token; output at max_output_tokens (%d) per call, its most; "
                "no cache hits;%s expected = halfway between solving and never finishing (docs/vlm.md, \"Cost before "
                "spending\")\n",
                e["max_output_tokens"].get<int>(), images ? " zoomed close-ups (view_zoom) not counted;" : "");
  out += line;
  if (e["stand_ins"].get<std::int64_t>() > 0) {
    out += "  " + grouped(e["stand_ins"].get<std::int64_t>()) +
           " episode(s) figured from another task of the same scene and level\n";
  }
  if (e["not_estimated"].get<std::int64_t>() > 0) {
    out += "  " + grouped(e["not_estimated"].get<std::int64_t>()) + " episode(s) not estimated: " +
           e["not_estimated_why"].get<std::string>() + "\n";
  }
  return out;
}

}  // namespace mtg::vlm
