#pragma once
// `mtg view` (the web viewer over run folders) and `mtg play` (a person plays episodes in the
// browser as the `human` agent), `mtg export` (the viewer as static files) (docs/view.md).

#include <cstdint>
#include <string>
#include <vector>

namespace mtg::cli {

struct ViewOptions {
  std::vector<std::string> runs;  // run folders
  std::string host = "127.0.0.1";
  int port = 8770;                // 0 = any free port
};

struct ExportOptions {
  std::vector<std::string> runs;  // run folders
  std::string out;                // a new or empty folder
};

struct PlayOptions {
  std::string tasks;
  std::string suite;              // or a suite file: its tasks (no --limit draw)
  std::string draw = "stratified";
  std::vector<std::string> scenes;
  std::string levels = "1,2,3";
  int limit = 1;                  // tasks per (scene, level)
  std::uint64_t seed = 0;
  std::string out = "play";       // run folder (resumable)
  std::string data_dir;
  std::string profile = "replica_cad";
  std::string url;                // LCM URL ("" = default)
  std::string host = "127.0.0.1";
  int port = 8780;
  int step_limit = 15;
  std::string lookalike_aid = "both";  // what the page gives of look-alikes (mtg run --lookalike-aid)
};

int run_view(const ViewOptions& options);
int run_play(const PlayOptions& options);
int run_export(const ExportOptions& options);

}  // namespace mtg::cli
