#include "orchestrator/cli/view_commands.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "agents/builtin/policies.h"
#include "bus/process/stop_signals.h"
#include "core/util/error.h"
#include "orchestrator/cli/run_commands.h"
#include "orchestrator/cli/serve_until_stopped.h"
#include "orchestrator/view/site_export.h"
#include "orchestrator/view/view_server.h"

namespace mtg::cli {

int run_view(const ViewOptions& o) {
  if (o.runs.empty()) throw Error("name at least one run folder");
  if (o.port < 0 || o.port > 65535) throw Error("--port must be 0..65535, not " + std::to_string(o.port));
  std::vector<std::filesystem::path> dirs(o.runs.begin(), o.runs.end());
  orchestrator::view::ViewServer server(dirs);
  server.bind(o.host, o.port);
  std::printf("viewing %zu run(s) at %s (Ctrl-C stops)\n", dirs.size(), server.url().c_str());
  std::fflush(stdout);
  serve_until_stopped(server);
  return 0;
}

int run_export(const ExportOptions& o) {
  if (o.out.empty()) throw Error("--out names the folder to export into");
  std::vector<std::filesystem::path> dirs(o.runs.begin(), o.runs.end());
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const auto start = std::chrono::steady_clock::now();  // telemetry only
  const auto stats = orchestrator::view::export_site(dirs, o.out, [&](std::size_t done, std::size_t total) {
    if (tty && (done % 50 == 0 || done == total)) std::fprintf(stderr, "\rexport: %zu/%zu episodes", done, total);
  });
  if (tty) std::fprintf(stderr, "\r\033[K");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("exported %zu episode(s) of %zu run(s) into %s: %zu page(s), %zu image file(s) for %zu shown, %.1f MiB "
              "in %.1f s\nopen %s/index.html (no server needed)\n",
              stats.episodes, stats.runs, o.out.c_str(), stats.attempts, stats.images, stats.image_refs,
              static_cast<double>(stats.bytes) / (1 << 20), seconds, o.out.c_str());
  // The site shows the damage; the command says it too, and does not claim a whole export.
  for (const std::string& line : stats.damage) std::fprintf(stderr, "mtg export: %s\n", line.c_str());
  if (!stats.damage.empty()) {
    std::fprintf(stderr, "mtg export: %zu damaged or missing stretch(es) of recording, named above and on the pages\n",
                 stats.damage.size());
    return 1;
  }
  return 0;
}

int run_play(const PlayOptions& o) {
  RunOptions r;
  r.tasks = o.tasks;
  r.suite = o.suite;
  r.draw = o.draw;
  r.agents = {agents::kHumanAgent};
  r.scenes = o.scenes;
  r.levels = o.levels;
  r.limit = o.limit;
  r.seed = o.seed;
  r.out = o.out;
  r.data_dir = o.data_dir;
  r.profile = o.profile;
  r.url = o.url;
  r.step_limit = o.step_limit;
  r.lookalike_aid = o.lookalike_aid;
  // One episode at a time, with the images a model sees, and time to think: an episode is
  // retried only after an hour without a move.
  r.parallel = 1;
  r.render = true;
  r.episode_timeout_s = 3600;
  r.play_host = o.host;
  r.play_port = o.port;
  r.given = {"--parallel", "--render", "--lookalike-aid"};
  // The page's address is printed once the human agent serves it (LocalRuntime::open).
  std::printf("playing into %s (Ctrl-C stops; the same command resumes)\n", o.out.c_str());
  std::fflush(stdout);
  return run_run(r);
}

}  // namespace mtg::cli
