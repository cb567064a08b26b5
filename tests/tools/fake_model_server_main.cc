// mtg_fake_model_server: the test suite's local model server as a program, for scripts/bench and
// for trying the adapters without an API key. It prints "port <n>" once listening, plays each
// task's oracle plan when given a task database, can enforce a requests-per-window limit with
// 429s, and on SIGINT/SIGTERM writes one JSON line per request it saw to --log.

#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <fstream>
#include <thread>

#include "core/tasks/task_db.h"
#include "tests/support/fake_model_server.h"

namespace {
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"local model server speaking the OpenAI, Anthropic and Gemini wire formats"};
  std::string tasks_db, log_file, address = "127.0.0.1";
  int rpm = 0, window_ms = 60000, latency_ms = 0;
  app.add_option("--tasks", tasks_db, "task database: answer with each task's oracle plan");
  app.add_option("--rpm", rpm, "answer 429 beyond this many requests per window (0 = no limit)");
  app.add_option("--window-ms", window_ms, "the limit's window (default 60000)");
  app.add_option("--latency-ms", latency_ms, "time each answer takes");
  app.add_option("--address", address, "address to listen on (default 127.0.0.1)");
  app.add_option("--log", log_file, "write the requests seen here (JSON lines) on exit");
  CLI11_PARSE(app, argc, argv);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    mtg::testing::FakeModelServer server(address);
    if (!tasks_db.empty()) {
      std::map<std::string, std::vector<std::string>> plans;
      for (const auto& t : mtg::tasks::read_tasks(tasks_db)) plans.emplace(t.text, t.oracle);
      server.set_model(mtg::testing::oracle_model(plans));
    }
    server.enforce_limit(rpm, std::chrono::milliseconds(window_ms));
    server.set_latency(std::chrono::milliseconds(latency_ms));
    std::printf("port %d\n", server.port());
    std::fflush(stdout);
    while (!g_stop) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!log_file.empty()) {
      std::ofstream out(log_file);
      for (const auto& r : server.requests()) {
        out << nlohmann::json({{"at_ms", r.at_ms}, {"status", r.status}, {"path", r.path}}).dump() << '\n';
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mtg_fake_model_server: %s\n", e.what());
    return 1;
  }
  return 0;
}
