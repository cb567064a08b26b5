#include "orchestrator/cli/vlm_commands.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "agents/vlm/bus_rate_gate.h"
#include "agents/vlm/encoding.h"
#include "agents/vlm/model_client.h"
#include "agents/vlm/model_setup.h"
#include "bus/bus.h"
#include "bus/process/identity.h"
#include "bus/url.h"
#include "core/util/error.h"

namespace mtg::cli {
namespace {

vlm::ImagePart read_image(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file + ": cannot read the image");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const bool jpeg = bytes.size() > 2 && bytes[0] == 0xFF && bytes[1] == 0xD8;
  const bool png = bytes.size() > 8 && bytes[0] == 0x89 && bytes[1] == 'P';
  if (!jpeg && !png) throw Error(file + ": not a PNG or JPEG file");
  return {jpeg ? "image/jpeg" : "image/png", vlm::base64_encode(bytes)};
}

}  // namespace

int run_vlm_ask(const VlmAskOptions& o) {
  if (o.repeat < 1 || o.parallel < 1) throw Error("mtg vlm ask: --repeat and --parallel must be at least 1");
  vlm::ModelSetup setup = vlm::ModelSetup::make(o.agent, o.vlm.resolve());
  vlm::ChatMessage user;
  user.text = o.text;
  for (const auto& f : o.images) user.images.push_back(read_image(f));

  std::unique_ptr<bus::Bus> bus;
  std::unique_ptr<bus::HeaderStamper> stamp;
  std::unique_ptr<vlm::RateGate> gate;
  vlm::BusRateGate* bus_gate = nullptr;
  if (o.bus_url.empty()) {
    gate = std::make_unique<vlm::LocalRateGate>(setup.limits());
  } else {
    bus = std::make_unique<bus::Bus>(bus::normalize_url(o.bus_url));
    stamp = std::make_unique<bus::HeaderStamper>("", process::sender_id("vlm-ask"));
    auto g = std::make_unique<vlm::BusRateGate>(*bus, *stamp, setup.limits());
    bus_gate = g.get();
    gate = std::move(g);
  }
  vlm::ModelClient client(setup.spec, setup.key, setup.settings, setup.prices, setup.cache.get(), gate.get());

  std::atomic<int> next{0}, running{o.parallel};
  std::mutex out_mutex;
  int ok = 0, failed = 0, hits = 0;
  double latency = 0.0, cost = 0.0;
  std::string last_error;
  bool stopped = false;
  auto work = [&] {
    for (int i = next++; i < o.repeat; i = next++) {
      const vlm::CallResult r = client.call(std::span<const vlm::ChatMessage>(&user, 1));
      std::lock_guard lock(out_mutex);
      ok += r.ok ? 1 : 0;
      failed += r.ok ? 0 : 1;
      hits += r.cache_hit ? 1 : 0;
      latency += r.latency_ms;
      cost += r.cost_usd;
      if (!r.ok) last_error = r.error;
      stopped = stopped || r.stop_agent;
      if (o.json) {
        const nlohmann::json line = {{"call", i},          {"ok", r.ok},
                                     {"text", r.text},      {"error", r.error},
                                     {"input_tokens", r.input_tokens}, {"output_tokens", r.output_tokens},
                                     {"cost_usd", r.cost_usd}, {"latency_ms", r.latency_ms},
                                     {"cache_hit", r.cache_hit}, {"http_attempts", r.http_attempts}};
        std::printf("%s\n", line.dump().c_str());
      } else if (o.repeat == 1) {
        if (r.ok) std::printf("%s\n", r.text.c_str());
        std::fprintf(stderr, "%s: %s, %d+%d tokens, $%.6f, %.0f ms%s\n", setup.spec.spec().c_str(),
                     r.ok ? "ok" : "failed", r.input_tokens, r.output_tokens, r.cost_usd, r.latency_ms,
                     r.cache_hit ? " (from the cache)" : "");
      }
      std::fflush(stdout);
    }
    --running;
  };
  std::vector<std::thread> threads;
  for (int k = 0; k < o.parallel; ++k) threads.emplace_back(work);
  // The bus thread: requests out, grants in, while the workers call.
  while (running > 0) {
    if (bus_gate != nullptr) {
      bus_gate->pump();
      bus->handle_once(5);
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  for (auto& t : threads) t.join();
  if (o.repeat > 1 && !o.json) {
    std::printf("%s: %d calls, %d ok, %d failed, %d from the cache, mean %.1f ms, $%.6f\n", setup.spec.spec().c_str(),
                o.repeat, ok, failed, hits, latency / o.repeat, cost);
  }
  if (failed > 0) {
    std::fprintf(stderr, "mtg vlm ask: %s\n", last_error.c_str());
    return 1;
  }
  return stopped ? 1 : 0;
}

}  // namespace mtg::cli
