#pragma once
// `mtg run`, `mtg report`, `mtg replay`, `mtg rejudge` (docs/runtime.md).

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "agents/vlm/options.h"
#include "orchestrator/remote/remote_options.h"
#include "orchestrator/remote/tcp_hub.h"

namespace mtg::cli {

struct RunOptions {
  std::string tasks;                 // task database
  std::string suite;                 // or a suite file (tasks/suite.h): exactly its tasks
  std::vector<std::string> agents;   // e.g. oracle, random
  std::vector<std::string> scenes;   // empty = all
  std::string levels = "1,2,3";
  int limit = 0;                     // tasks per (scene, level); 0 = all
  std::string draw = "stratified";   // how --limit draws (tasks/draw.h)
  bool estimate = false;             // --estimate: print the cost estimate and exit, running nothing
  double max_cost_usd = 0.0;         // --max-cost: US$ cap on the run's spending (0 = none; docs/vlm.md)
  int repeat = 1;                    // episodes per (task, agent)
  int parallel = 0;                  // when not given: 4, or with --remote as many as the workers take
  std::uint64_t seed = 0;
  bool render = false;               // --render: images even for built-in agents
  int renderers = 0;                 // renderer processes here (0 = render::default_renderers)
  std::string recordings;            // --recordings: coordinator (default), shared:PATH, worker
  bool no_render = false;            // --no-render: text only even for model agents
  std::string image_size = "640x480";
  std::string image_encoding = "png";
  std::string object_names = "auto"; // on, off, or auto: on for text-only runs and name-rule task sets
  std::string lookalike_aid = "both";  // --lookalike-aid: image, words or both (episode::LookalikeAid)
  std::string out;                   // run folder
  std::string data_dir;
  std::string profile = "replica_cad";
  std::string url;                   // LCM URL ("" = default)
  double episode_timeout_s = -1.0;   // -1 = 60 s, or 900 s with a model agent (API retries)
  int step_limit = 15;
  bool no_progress = false;
  std::string recorder = "mtg";      // or lcm-logger
  vlm::VlmOptions vlm;               // for model agents (forwarded to every adapter)
  bool remote = false;               // episodes run on `mtg worker`s of the bus, by lease
  orchestrator::remote::RemoteOptions remote_options;
  bool allow_data_mismatch = false;  // run on a dataset other than the task set's
  // --slurm "<sbatch options>" (given = on, even empty): the workers are a Slurm job array.
  std::string slurm;
  int slurm_workers = 1;             // with --slurm: array tasks, one worker each
  int worker_capacity = 2;           // with --slurm: episodes at once per worker
  int hub_port = orchestrator::remote::kDefaultHubPort;  // with --slurm and no --bus: this run's hub
  std::string hub_host;              // ... as the nodes reach it ("" = this host's name)
  std::string play_host = "127.0.0.1";  // the human agent's play page (mtg play)
  int play_port = 8780;
  std::set<std::string> given;       // the options given on the command line ("--levels", ...)
  std::vector<std::string> command_line;  // argv, for the run's provenance
};

struct ReportOptions {
  std::string run;
  std::string html;  // "" = <run>/report.html
  bool json = false;
  bool card = false;  // also card.md and card.json (report/card.h)
};

struct CompareOptions {
  std::string run_a;     // the baseline run
  std::string run_b;     // "" = compare the agents of run_a with one of them
  std::string agent;     // "" = every agent (both runs) or every agent but the baseline (one run)
  std::string baseline;  // one run: the baseline agent ("" = the run's first agent)
  bool json = false;
};

struct ReplayOptions {
  std::string run;
  std::string out;   // "" = <run>/replay
  std::string url;
  int parallel = 4;
};

int run_run(const RunOptions& options);
int run_report(const ReportOptions& options);
int run_compare(const CompareOptions& options);
int run_replay(const ReplayOptions& options);
int run_rejudge(const std::string& run);

}  // namespace mtg::cli
