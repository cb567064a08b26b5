// mtg_bench_vlm (scripts/bench vlm): the model adapters' figures against the local model server.
//   1. adapter overhead per call, excluding the server: a step's request (prompt, history, two
//      640x480 observation images) through ModelClient, minus the server's own handling time;
//   2. requests per minute held by the governor with 8 parallel episodes, against a server that
//      answers 429 beyond the same limit (none may reach a result);
//   3. the cache on a rerun: hit rate and HTTP calls.

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "agents/vlm/conversation.h"
#include "agents/vlm/model_client.h"
#include "agents/vlm/model_setup.h"
#include "core/tasks/task_db.h"
#include "core/util/rng.h"
#include "orchestrator/run/results_db.h"
#include "tests/support/fake_model_server.h"
#include "tests/support/process.h"

namespace {

namespace fs = std::filesystem;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// A 640x480 PNG with texture, about the size of a rendered observation.
std::vector<std::uint8_t> observation_png(std::uint64_t seed) {
  cv::Mat img(480, 640, CV_8UC3);
  mtg::Rng rng(seed);
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      const auto n = static_cast<unsigned char>(rng.uniform_index(40));
      img.at<cv::Vec3b>(y, x) = {static_cast<unsigned char>(x / 3 + n), static_cast<unsigned char>(y / 2 + n), 120};
    }
  }
  std::vector<std::uint8_t> png;
  cv::imencode(".png", img, png);
  return png;
}

int run(const std::vector<std::string>& argv, const fs::path& log) {
  mtg::testing::ChildProcess p(argv, log.string());
  return p.wait(3600 * 1000);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"model adapter figures (scripts/bench vlm)"};
  std::string tasks_db, data_dir, work = "/tmp/mtg_bench_vlm", scene = "apt_0";
  int calls = 200, episodes = 48, rpm = 120, parallel = 8;
  app.add_option("--tasks", tasks_db, "task database for the episode part")->required();
  app.add_option("--data", data_dir, "dataset root");
  app.add_option("--work", work, "scratch folder (emptied first)");
  app.add_option("--calls", calls, "calls for the overhead figure");
  app.add_option("--episodes", episodes, "episodes for the governor figure");
  app.add_option("--rpm", rpm, "requests per minute for the governor and the server");
  app.add_option("--parallel", parallel, "episodes in flight");
  CLI11_PARSE(app, argc, argv);
  fs::remove_all(work);
  fs::create_directories(work);
  const std::string key = "sk-bench-0123456789";
  ::setenv("OPENAI_API_KEY", key.c_str(), 1);
  ::setenv("MTG_CACHE_DIR", (fs::path(work) / "cache").c_str(), 1);

  // 1. Overhead per call.
  {
    mtg::testing::FakeModelServer server;
    mtg::vlm::VlmSettings settings;
    settings.no_cache = true;
    settings.base_url = server.url() + "/v1";
    mtg::vlm::ModelSetup setup = mtg::vlm::ModelSetup::make("openai:gpt-4o", settings);
    mtg::vlm::ModelClient client(setup.spec, setup.key, setup.settings, setup.prices, nullptr, nullptr);
    std::vector<double> total, text_total;
    for (int i = 0; i < calls; ++i) {
      // Each call a new step: fresh images (as a new observation brings), so nothing is reused.
      mtg::observation_t obs{};
      obs.step = 3;
      obs.step_limit = 15;
      obs.task_text = "Move the bowl from the kitchen counter to the sofa table.";
      obs.text = "You are standing at the front side of platform l12. You hold nothing.";
      for (int k = 1; k <= 60; ++k) {
        mtg::action_option_t a{};
        a.key = "l" + std::to_string(k);
        a.description = "go to platform " + std::to_string(k);
        obs.actions.push_back(a);
      }
      for (const char* role : {"view_marked", "item"}) {
        mtg::image_t img{};
        img.role = role;
        img.encoding = "png";
        img.width = 640;
        img.height = 480;
        img.data = observation_png(static_cast<std::uint64_t>(i * 2 + (role[0] == 'i')));
        obs.images.push_back(img);
      }
      const auto t0 = std::chrono::steady_clock::now();
      mtg::episode_start_t start{};
      start.step_limit = 15;
      mtg::vlm::Conversation conv(setup.prompts, setup.settings, start);
      const auto messages = conv.ask(obs);
      const mtg::vlm::CallResult r = client.call(messages);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (!r.ok) {
        std::fprintf(stderr, "bench_vlm: call failed: %s\n", r.error.c_str());
        return 1;
      }
      total.push_back(ms);
      mtg::vlm::ChatMessage text{mtg::vlm::ChatMessage::Role::kUser, obs.text, {}};
      const auto t1 = std::chrono::steady_clock::now();
      (void)client.call(std::span<const mtg::vlm::ChatMessage>(&text, 1));
      text_total.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count());
    }
    std::vector<double> image_server, text_server;
    const auto seen = server.requests();
    for (std::size_t i = 0; i < seen.size(); ++i) (i % 2 == 0 ? image_server : text_server).push_back(seen[i].handle_ms);
    const std::size_t body = seen.empty() ? 0 : seen.front().body.size();
    std::printf("  adapter overhead per call, server time excluded (median of %d; loopback HTTP, no TLS):\n", calls);
    std::printf("    observation step (2 PNG images, %zu KiB request): %.2f ms  (client %.2f ms - server %.2f ms)\n",
                body / 1024, median(total) - median(image_server), median(total), median(image_server));
    std::printf("    text-only call:                                  %.2f ms  (client %.2f ms - server %.2f ms)\n",
                median(text_total) - median(text_server), median(text_total), median(text_server));
  }

  // 2. and 3. Episodes with 8 in flight under the governor; then a cached rerun.
  mtg::testing::FakeModelServer server;
  std::map<std::string, std::vector<std::string>> plans;
  for (const auto& t : mtg::tasks::read_tasks(tasks_db)) plans.emplace(t.text, t.oracle);
  server.set_model(mtg::testing::oracle_model(plans));
  server.enforce_limit(rpm, std::chrono::minutes(1));
  server.set_latency(std::chrono::milliseconds(300));  // a fast real model's answer time
  ::setenv("OPENAI_BASE_URL", (server.url() + "/v1").c_str(), 1);
  const fs::path bin = fs::path(mtg::testing::bin("mtg"));
  auto run_args = [&](const std::string& out, const std::vector<std::string>& extra) {
    std::vector<std::string> a = {bin.string(), "run", "--tasks", tasks_db, "--scene", scene, "--levels", "1",
                                  "--limit", std::to_string(episodes), "--parallel", std::to_string(parallel),
                                  "--agent", "openai:gpt-4o", "--out", (fs::path(work) / out).string(),
                                  "--no-progress", "--rpm", std::to_string(rpm)};
    if (!data_dir.empty()) a.insert(a.end(), {"--data", data_dir});
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const auto t0 = std::chrono::steady_clock::now();
  if (run(run_args("run", {}), fs::path(work) / "run.log") != 0) {
    std::fprintf(stderr, "bench_vlm: the governed run failed, see %s/run.log\n", work.c_str());
    return 1;
  }
  const double run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto seen = server.requests();
  int max_in_minute = 0;
  for (const auto& s : seen) {
    int n = 0;
    for (const auto& o : seen) n += o.at_ms >= s.at_ms && o.at_ms < s.at_ms + 60000.0;
    max_in_minute = std::max(max_in_minute, n);
  }
  const double span_min = seen.size() > 1 ? (seen.back().at_ms - seen.front().at_ms) / 60000.0 : 0.0;
  const auto rows = mtg::orchestrator::read_results(fs::path(work) / "run" / "results.sqlite");
  int success = 0, provider_errors = 0, calls_made = 0;
  for (const auto& r : rows) {
    success += r.success;
    provider_errors += r.cause == "provider_error";
    calls_made += r.usage.model_calls;
  }
  std::printf("  governor: %d episodes, %d in flight, limit %d requests/min (server enforces the same):\n",
              static_cast<int>(rows.size()), parallel, rpm);
  std::printf("    %zu requests in %.1f s (run %.1f s); busiest 60 s window: %d requests (limit %d)\n", seen.size(),
              span_min * 60.0, run_s, max_in_minute, rpm);
  std::printf("    429 answers from the server: %d; results with provider_error: %d; SR %d/%zu\n",
              server.answered_429(), provider_errors, success, rows.size());

  const std::size_t before = server.requests().size();
  if (run(run_args("rerun", {"--cache-only"}), fs::path(work) / "rerun.log") != 0) {
    std::fprintf(stderr, "bench_vlm: the cached rerun failed, see %s/rerun.log\n", work.c_str());
    return 1;
  }
  const auto again = mtg::orchestrator::read_results(fs::path(work) / "rerun" / "results.sqlite");
  int hits = 0, rerun_calls = 0, same = 0;
  for (std::size_t i = 0; i < again.size(); ++i) {
    hits += again[i].usage.cache_hits;
    rerun_calls += again[i].usage.model_calls;
    same += i < rows.size() &&
            mtg::orchestrator::verdict_fingerprint(again[i]) == mtg::orchestrator::verdict_fingerprint(rows[i]);
  }
  std::printf("  cached rerun (--cache-only): %d of %d answers from the cache (%.1f %%), %zu HTTP calls, "
              "%d/%zu verdicts identical\n",
              hits, rerun_calls, rerun_calls ? 100.0 * hits / rerun_calls : 0.0, server.requests().size() - before,
              same, again.size());
  (void)calls_made;
  return 0;
}
