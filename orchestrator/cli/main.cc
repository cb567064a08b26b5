// The `mtg` front end: parses the command line and hands each subcommand a plain options struct.
// Exit codes: 0 success, 1 bad input or failure (one line on stderr), 2 usage error.

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "core/util/error.h"
#include "core/util/log.h"
#include "orchestrator/cli/audit_commands.h"
#include "orchestrator/cli/sight_commands.h"
#include "orchestrator/cli/suite_commands.h"
#include "orchestrator/cli/bench_commands.h"
#include "orchestrator/cli/cluster_commands.h"
#include "orchestrator/cli/leaderboard_commands.h"
#include "orchestrator/cli/render_commands.h"
#include "orchestrator/cli/run_commands.h"
#include "orchestrator/cli/scene_commands.h"
#include "orchestrator/cli/task_commands.h"
#include "orchestrator/cli/view_commands.h"
#include "orchestrator/cli/vlm_commands.h"
#include "orchestrator/run/page_relay.h"
#include "orchestrator/run/run_namespace.h"

// Two programs from this file (docs/build.md, "Libraries loaded at start"): `mtg_cli`, every
// command, and `mtg`, the front a user runs. The front knows every option (so --help, and every
// refusal of a command line, answer from it at once) but links no library of ours: once a
// command line parses, it runs mtg_cli beside it with the same arguments (exec: the same
// process, the same pid). mtg_cli loads 74 libraries at start; the front 5.
#ifdef MTG_CLI_FRONT
#define MTG_COMMAND(...) (void)0
#else
#define MTG_COMMAND(...) commands.push_back(__VA_ARGS__)
#endif

namespace mtg::cli {
namespace {

// A leaf command: its CLI11 node, and what runs when it was the one parsed. Options live in
// shared structs the runner holds, so each group registers itself in one function.
struct Command {
  CLI::App* app;
  std::function<int()> run;
  // Commands whose own output is the point (an image, an audit page): the library's progress
  // notes ("loaded scene", "renderer: ...") stay off the terminal unless --log-level asks.
  bool quiet_by_default = false;
};
// The commands, and the option structs CLI11 writes into while it parses: kept here so they
// outlive the parse (the front drops the runners, which held them before).
struct Commands {
  std::vector<Command> list;
  std::vector<std::shared_ptr<void>> options;
  void push_back(Command c) { list.push_back(std::move(c)); }
};

template <class Options>
std::shared_ptr<Options> options(Commands& commands) {
  auto o = std::make_shared<Options>();
  commands.options.push_back(o);
  return o;
}

// "mtg <subcommand>: <message>", once: a message that already names its command keeps its name.
#ifdef MTG_CLI_FRONT
// Runs mtg_cli, the program beside this one, in this process with these arguments.
int run_beside(char** argv) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path cli = self.parent_path() / "mtg_cli";
  if (!ec) ::execv(cli.c_str(), argv);
  std::cerr << "mtg: cannot run " << (ec ? std::string("mtg_cli (no /proc/self/exe)") : cli.string()) << ": "
            << std::strerror(ec ? ec.value() : errno) << " (it is built beside mtg; rebuild with scripts/build)\n";
  return 1;
}
#endif

[[maybe_unused]] std::string where(const CLI::App& app, const std::string& message) {
  std::string who = "mtg";
  for (const CLI::App* sub = &app; !sub->get_subcommands().empty();) {
    sub = sub->get_subcommands().front();
    who += " " + sub->get_name();
  }
  if (message.rfind(who + ":", 0) == 0) return message;
  if (message.rfind("mtg ", 0) == 0) return message;
  return who + ": " + message;
}

// mtg scene list | info | graph
void add_scene_commands(CLI::App& app, Commands& commands) {
  CLI::App* scene = app.add_subcommand("scene", "Inspect scenes of the dataset");
  scene->require_subcommand(1);
  auto list_opts = options<SceneListOptions>(commands);
  CLI::App* scene_list = scene->add_subcommand("list", "List the scenes found in the dataset");
  scene_list->add_option("--data", list_opts->data_dir, "dataset root (default: search order)");
  auto info_opts = options<SceneInfoOptions>(commands);
  CLI::App* scene_info = scene->add_subcommand("info", "Load a scene and summarise it");
  scene_info->add_option("--scene", info_opts->scene, "scene name, e.g. apt_0")->required();
  scene_info->add_option("--data", info_opts->data_dir, "dataset root (default: search order)");
  scene_info->add_flag("--json", info_opts->json, "print one JSON object");
  scene_info->add_flag("--files", info_opts->files,
                       "print the files the scene is made from, relative to the dataset root (to copy a scene)")
      ->excludes("--json");

  auto graph_opts = options<SceneGraphOptions>(commands);
  CLI::App* scene_graph = scene->add_subcommand("graph", "Build the scene graph of a scene");
  scene_graph->add_option("--scene", graph_opts->scene, "scene name, e.g. apt_0")->required();
  scene_graph->add_option("--data", graph_opts->data_dir, "dataset root (default: search order)");
  scene_graph->add_option("--out", graph_opts->out, "write graph.json here");
  scene_graph->add_option("--png", graph_opts->png, "write a top-down map (PNG) here");
  scene_graph->add_option("--profile", graph_opts->profile,
                          "scene profile: replica_cad (default), none, or a JSON file");
  MTG_COMMAND({scene_list, [list_opts] { return run_scene_list(*list_opts); }});
  MTG_COMMAND({scene_info, [info_opts] { return run_scene_info(*info_opts); }});
  MTG_COMMAND({scene_graph, [graph_opts] { return run_scene_graph(*graph_opts); }});
  auto remix_opts = options<SceneRemixOptions>(commands);
  CLI::App* scene_remix = scene->add_subcommand(
      "remix", "Write a scene with its items put elsewhere (a held-out arrangement), as a dataset folder");
  scene_remix->add_option("--scene", remix_opts->scene, "scene name, e.g. apt_0")->required();
  scene_remix->add_option("--data", remix_opts->data_dir, "dataset root (default: search order)");
  scene_remix->add_option("--profile", remix_opts->profile, "scene profile (default replica_cad)");
  scene_remix->add_option("--seed", remix_opts->seed, "seed of the arrangement (default 1)");
  scene_remix->add_option("--name", remix_opts->name, "the new scene's name (default <scene>_remix_<seed>)");
  scene_remix->add_option("--out", remix_opts->out, "dataset folder to write or add to")->required();
  MTG_COMMAND({scene_remix, [remix_opts] { return run_scene_remix(*remix_opts); }});
}

// mtg render | images
void add_render_commands(CLI::App& app, Commands& commands) {
  auto render_opts = options<RenderOptions>(commands);
  CLI::App* render = app.add_subcommand("render", "Render one view of a scene as the agent sees it");
  render->add_option("--scene", render_opts->scene, "scene name, e.g. apt_0")->required();
  render->add_option("--data", render_opts->data_dir, "dataset root (default: search order)");
  render->add_option("--profile", render_opts->profile, "scene profile (default replica_cad)");
  render->add_option("--view", render_opts->view,
                     "platform (default), item (with what rests on it), focus (in place, neighbours faded) or topdown")
      ->check(CLI::IsMember({"platform", "item", "focus", "topdown"}));
  render->add_option("--platform", render_opts->platform, "platform name (platform views)");
  render->add_option("--side", render_opts->side, "0 rear, 1 left, 2 front, 3 right (default: the platform's default side)")
      ->check(CLI::Range(-1, 3));
  render->add_option("--item", render_opts->item, "object name (item views)");
  render->add_option("--marks", render_opts->marks, "auto (default), items, targets, labels or none")
      ->check(CLI::IsMember({"auto", "items", "targets", "labels", "none"}));
  render->add_option("--width", render_opts->width, "pixels (default 640)");
  render->add_option("--height", render_opts->height, "pixels (default 480)");
  render->add_option("--out", render_opts->out, "image file (.png or .jpg); the marked copy goes to <stem>_marked")
      ->required();
  render->add_option("--ids", render_opts->ids, "also write the id pass (16-bit PNG: object index + 1, 0 nothing)");
  render->add_option("--marks-json", render_opts->marks_json,
                     "also write the legend (each object's visible pixels) and where each mark went (JSON)");
  render->add_option("--tasks", render_opts->tasks, "task database, for --task");
  render->add_option("--task", render_opts->task, "draw where this task's part starts, at its item's platform");
  render->add_option("--part", render_opts->part, "the task's part (Level 3: 0, 1, ...; default 0)");
  render->add_flag("--holding", render_opts->holding, "once the part's item is picked, at its destination");

  auto images_opts = options<ImagesOptions>(commands);
  CLI::App* images = app.add_subcommand("images", "Write the images the agents saw in a run to files");
  images->add_option("run", images_opts->run, "run folder")->required();
  images->add_option("--out", images_opts->out, "folder for the image files")->required();
  images->add_option("--episode", images_opts->episode, "only this episode id");
  MTG_COMMAND({render, [render_opts] { return run_render(*render_opts); }, true});
  MTG_COMMAND({images, [images_opts] { return run_images(*images_opts); }, true});
}

// mtg tasks [stats DB]
void add_task_commands(CLI::App& app, Commands& commands) {
  auto tasks_opts = options<TasksOptions>(commands);
  CLI::App* tasks = app.add_subcommand("tasks", "Generate task sets (Levels 1-4) into SQLite/JSONL");
  tasks->require_subcommand(0, 1);
  tasks->add_option("--scene", tasks_opts->scenes, "scene name (repeat for several)");
  tasks->add_option("--data", tasks_opts->data_dir, "dataset root (default: search order)");
  tasks->add_option("--out", tasks_opts->out, "task database to write (SQLite)");
  tasks->add_option("--jsonl", tasks_opts->jsonl, "also export one task per line here");
  tasks->add_option("--seed", tasks_opts->seed, "seed (default 0)");
  tasks->add_option("--jobs", tasks_opts->jobs, "threads (default: the machine's cores); the tasks do not depend on it");
  tasks->add_option("--levels", tasks_opts->levels, "levels to generate, e.g. 1,2,3,4");
  tasks->add_option("--profile", tasks_opts->profile, "scene profile (replica_cad, none, or a file)");
  tasks->add_option("--ambiguity", tasks_opts->ambiguity, "Look-alike rule: noun (default: what a person calls it, the scene profile's noun table, for agents that see images), category (the dataset's semantic class) or name (the same model, for agents told object names)");
  tasks->add_option("--visibility", tasks_opts->visibility,
                    "on (default): a task names and counts only what its arrival view clearly shows; off: the "
                    "geometry alone decides (for comparisons: such tasks may name what the agent cannot see)");
  tasks->add_option("--l3-count", tasks_opts->level3_count, "Level 3 tasks per scene (default 10000)");
  tasks->add_option("--l3-chain", tasks_opts->level3_chain, "sub-tasks per Level 3 task (default 2)");
  tasks->add_option("--l4-max-moves", tasks_opts->level4_max_moves, "objects a Level 4 task may move (default 3)");
  tasks->add_option("--l4-max-share", tasks_opts->level4_max_kind_share,
                    "largest share of Level 4 one outcome kind may hold (default 0.2; 1: no cap)");
  tasks->add_option("--l4-templates", tasks_opts->level4_templates, "Level 4 template library (builtin or a file)");
  tasks->add_option("--votes", tasks_opts->votes, "recorded Level 4 feasibility votes (JSONL)");
  tasks->add_option("--step-limit", tasks_opts->step_limit, "episode step limit (default 15)");
  tasks->add_option("--voter", tasks_opts->voters, "model agent voting live on Level 4 candidates (repeatable)");
  mtg::vlm::add_vlm_options(*tasks, tasks_opts->vlm, true);
  auto stats_opts = options<TaskStatsOptions>(commands);
  CLI::App* tasks_stats = tasks->add_subcommand("stats", "Counts per level, type and scene of a task database");
  tasks_stats->add_option("db", stats_opts->db, "task database")->required();
  tasks_stats->add_flag("--json", stats_opts->json, "print one JSON object");
  // Before its parent: when `tasks stats` is given, both are parsed.
  MTG_COMMAND({tasks_stats, [stats_opts] { return run_task_stats(*stats_opts); }});
  MTG_COMMAND({tasks, [tasks_opts] { return run_tasks(*tasks_opts); }});
}

// mtg run | worker | status
void add_run_commands(CLI::App& app, Commands& commands, [[maybe_unused]] char** argv) {
  auto run_opts = options<RunOptions>(commands);
  CLI::App* run = app.add_subcommand("run", "Run a benchmark: episodes of a task set with agents, over LCM");
  run->add_option("--tasks", run_opts->tasks, "task database (tasks.sqlite)");
  run->add_option("--suite", run_opts->suite,
                  "a suite file (mtg suite make): run exactly its tasks, with no task set at hand")
      ->excludes("--tasks");
  run->add_option("--agent", run_opts->agents,
                  "agent: oracle, random, replay:<run dir>, script:<file>, human, openai:<model>, anthropic:<model>, "
                  "gemini:<model>, openai-compatible:<url>:<model> (repeat for several)");
  run->add_option("--scene", run_opts->scenes, "only tasks of this scene (repeat for several; default all)");
  run->add_option("--levels", run_opts->levels, "levels to run (default 1,2,3)");
  run->add_option("--limit", run_opts->limit, "tasks per scene and level, drawn with the seed (default all)");
  run->add_option("--draw", run_opts->draw,
                  "how --limit draws: stratified (default: round-robin over platforms and item models, outcome "
                  "kinds and templates) or uniform")
      ->check(CLI::IsMember({"stratified", "uniform"}));
  run->add_flag("--estimate", run_opts->estimate,
                "print what the model agents would cost and take (docs/vlm.md, \"Cost before spending\") and exit");
  run->add_option("--max-cost", run_opts->max_cost_usd,
                  "US$: start no episode once spent plus expected in flight reaches it; exits 3 (0 = no cap)")
      ->check(CLI::NonNegativeNumber);
  run->add_option("--repeat", run_opts->repeat,
                  "episodes per task and agent, each with its own episode seed (default 1; a random agent's spread, "
                  "long soaks)");
  run->add_option("--parallel", run_opts->parallel,
                  "episodes at once (default 4; with --remote: what the workers' capacities allow)");
  run->add_option("--seed", run_opts->seed, "run seed (default 0)");
  run->add_flag("--render", run_opts->render, "observations carry images (default: only for model agents)");
  run->add_flag("--no-render", run_opts->no_render, "text-only observations, for any agent");
  run->add_option("--renderers", run_opts->renderers,
                  "renderer processes on this machine (default 0: one per four cores, at least one per GPU)")
      ->check(CLI::Range(0, 256));
  run->add_option("--image-size", run_opts->image_size, "observation images WIDTHxHEIGHT (default 640x480)");
  run->add_option("--image-encoding", run_opts->image_encoding, "png (default) or jpeg")
      ->check(CLI::IsMember({"png", "jpeg"}));
  run->add_option("--object-names", run_opts->object_names,
                  "name objects in the action space: on, off, or auto (default: on without images or for a "
                  "task set of the name rule; the paper's numbered objects otherwise)")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  run->add_option("--lookalike-aid", run_opts->lookalike_aid,
                  "how look-alikes are told apart: both (default: the words and a close-up of each, as the paper), "
                  "words (the words alone) or image (the close-ups alone; needs images)")
      ->check(CLI::IsMember({"both", "words", "image"}));
  run->add_option("--out", run_opts->out, "run folder (a second run on it resumes)")->required();
  run->add_option("--data", run_opts->data_dir, "dataset root (default: search order)");
  run->add_flag("--allow-data-mismatch", run_opts->allow_data_mismatch,
                "run even where the dataset differs from the one the task set was made from");
  run->add_option("--profile", run_opts->profile, "scene profile (default replica_cad)");
  run->add_option("--url,--bus", run_opts->url, "LCM URL (default $MTG_LCM_URL or the loopback group)");
  run->add_flag("--remote", run_opts->remote, "run the episodes on the workers of the bus (`mtg worker`), by lease");
  run->add_option("--bus-key", run_opts->remote_options.bus_key,
                  "with --remote: the shared bus's key file, the same on every host (default $MTG_BUS_KEY)");
  run->add_option("--recordings", run_opts->recordings,
                  "with --remote/--slurm: where each episode's recording goes: coordinator (default: sent here), "
                  "shared:PATH (a folder every host sees; only a reference crosses the bus) or worker (kept on "
                  "each worker; `mtg gather` brings them in)");
  run->add_option("--min-workers", run_opts->remote_options.min_workers, "with --remote: workers to wait for (default 1)");
  run->add_option("--worker-wait", run_opts->remote_options.worker_wait_s, "with --remote: seconds to wait for them (default 600)");
  run->add_option("--lease-ttl", run_opts->remote_options.lease_ttl_s,
                  "with --remote: seconds without renewal before a lease is re-issued (default 5)");
  run->add_option("--slurm", run_opts->slurm,
                  "start the workers as a Slurm job array, with these sbatch options (\"\" for none); implies --remote")
      ->expected(0, 1);
  run->add_option("--slurm-workers", run_opts->slurm_workers, "with --slurm: workers, one array task each (default 1)");
  run->add_option("--worker-capacity", run_opts->worker_capacity, "with --slurm: episodes at once per worker (default 2)");
  run->add_option("--hub-port", run_opts->hub_port, "with --slurm and no --bus: port of the run's LCM hub (default: the first free from 7700)");
  run->add_option("--hub-host", run_opts->hub_host,
                  "with --slurm and no --bus: this host's name or address as the nodes reach it (default: host name)");
  run->add_option("--episode-timeout", run_opts->episode_timeout_s, "seconds without news before a retry (default 60)");
  run->add_option("--step-limit", run_opts->step_limit, "steps per episode (default 15)");
  run->add_flag("--no-progress", run_opts->no_progress, "no progress bar");
  run->add_option("--recorder", run_opts->recorder, "mtg (default) or lcm-logger (drops bursts on a busy machine)");
  mtg::vlm::add_vlm_options(*run, run_opts->vlm, true);
  // mtg worker / mtg status
  auto worker_opts = options<WorkerCliOptions>(commands);
  CLI::App* worker = app.add_subcommand("worker", "Run the episodes a coordinator (mtg run --remote) leases to this host");
  worker->add_option("--bus", worker_opts->worker.bus_url,
                     "the shared LCM URL: udpm://<group>:<port>?ttl=1, or tcpq://<hub host>:<port> (mtg hub)")
      ->required();
  worker->add_option("--bus-key", worker_opts->worker.bus_key,
                     "the shared bus's key file, the same on every host (default $MTG_BUS_KEY)");
  worker->add_option("--local-url", worker_opts->worker.local_url,
                     "this host's own bus (default: a network namespace of the worker's own, else the loopback group on a port no other bus here uses)");
  worker->add_option("--run", worker_opts->worker.run_id, "join only this run id (default: the first announced)");
  worker->add_option("--capacity", worker_opts->worker.capacity, "episodes at once (default 2)");
  worker->add_option("--name", worker_opts->worker.name, "name shown by mtg status (default: the host name)");
  worker->add_option("--dir", worker_opts->worker.dir, "folder for process logs and this host's recordings (default ./mtg-worker)");
  worker->add_option("--data", worker_opts->worker.data_dir, "dataset root on this host (default: the coordinator's path)");
  worker->add_option("--recorder", worker_opts->worker.recorder, "mtg (default) or lcm-logger");
  worker->add_option("--renderers", worker_opts->worker.renderers,
                     "renderer processes on this host for runs with images (default 0: one per four cores, at least one per GPU)")
      ->check(CLI::Range(0, 256));
  worker->add_option("--chunk-bytes", worker_opts->worker.chunk_bytes, "recording chunk size (default 32768)");
  worker->add_flag("--once", worker_opts->worker.once, "exit after one run");
  mtg::vlm::add_vlm_options(*worker, worker_opts->vlm, false);
  auto status_opts = options<StatusOptions>(commands);
  CLI::App* status = app.add_subcommand("status", "Hosts, episodes in flight, rates and SR/IP of the runs on a bus");
  status->add_option("--bus", status_opts->bus_url, "LCM URL (default $MTG_LCM_URL or the loopback group)");
  status->add_option("--bus-key", status_opts->bus_key,
                     "the shared bus's key file: only messages signed with it are shown (default $MTG_BUS_KEY)");
  status->add_option("--listen", status_opts->listen_s, "seconds to listen (default 2.5)");
  status->add_flag("--json", status_opts->json, "print one JSON object");
  MTG_COMMAND({run, [run, run_opts, argv]() -> int {
                        for (const CLI::Option* opt : run->get_options()) {
                          if (opt->count() > 0) run_opts->given.insert(opt->get_name());
                        }
                        if (run_opts->given.count("--slurm")) run_opts->remote = true;
                        for (char** a = argv; *a != nullptr; ++a) run_opts->command_line.emplace_back(*a);
                        // A run on this machine gets a bus of its own (run_namespace.h), unless told which to use.
                        if (run_opts->url.empty() && !run_opts->remote && !run_opts->estimate) {
                          if (const auto isolated = orchestrator::run_in_own_namespace(argv)) return *isolated;
                        }
                        return run_run(*run_opts);
                      }});
  auto gather_opts = options<GatherCliOptions>(commands);
  CLI::App* gather = app.add_subcommand(
      "gather", "Bring a multi-host run's recordings kept on its workers (--recordings worker) into the run folder");
  gather->add_option("run", gather_opts->run, "run folder")->required();
  gather->add_option("--from", gather_opts->from, "a copy of a worker's --dir to take them from first (repeatable)");
  gather->add_flag("--no-bus", gather_opts->no_bus, "do not ask the workers over the bus");
  gather->add_option("--bus", gather_opts->bus_url, "the shared bus (default: the run's)");
  gather->add_option("--bus-key", gather_opts->bus_key,
                     "its key file (default $MTG_BUS_KEY, else the run folder's bus.key)");
  gather->add_option("--wait", gather_opts->wait_s, "seconds without a new recording before giving up (default 30)");
  MTG_COMMAND({gather, [gather_opts] { return run_gather(*gather_opts); }});
  auto hub_opts = options<HubOptions>(commands);
  CLI::App* hub = app.add_subcommand("hub", "The shared bus without multicast: LCM's TCP hub (join with --bus tcpq://HOST:PORT)");
  hub->add_option("--port", hub_opts->port, "TCP port (default 7700)");
  hub->add_flag("--quiet", hub_opts->quiet, "without the once-a-second throughput line");
  MTG_COMMAND({hub, [hub_opts]() -> int { run_hub(*hub_opts); }});
  MTG_COMMAND({worker, [worker_opts] { return run_worker(*worker_opts); }});
  MTG_COMMAND({status, [status_opts] { return run_status(*status_opts); }});
}

// mtg suite make | info | verify
void add_suite_commands(CLI::App& app, Commands& commands) {
  CLI::App* suite = app.add_subcommand("suite", "Frozen samples of tasks to run and cite (docs/suites.md)");
  suite->require_subcommand(1);
  auto make_opts = options<SuiteMakeOptions>(commands);
  CLI::App* make = suite->add_subcommand("make", "Draw a stratified sample of a task set into one self-contained suite file");
  make->add_option("--tasks", make_opts->tasks, "task database to draw from")->required();
  make->add_option("--scene", make_opts->scenes, "only this scene (repeat for several; default all of the set)");
  make->add_option("--levels", make_opts->levels, "levels (default 1,2,3,4)");
  make->add_option("--per-level", make_opts->per_level, "tasks per scene and level");
  make->add_option("--mde", make_opts->mde,
                   "instead of --per-level: the SR difference (points) a paired comparison of two agents should detect");
  make->add_option("--power", make_opts->power, "with --mde: power (default 0.8)");
  make->add_option("--discordance", make_opts->discordance,
                   "with --mde: expected share of tasks where exactly one of two agents succeeds (default 0.3)");
  make->add_option("--alpha", make_opts->alpha, "with --mde: two-sided significance level (default 0.05)");
  make->add_option("--seed", make_opts->seed, "seed of the draw (default 0)");
  make->add_option("--draw", make_opts->draw, "stratified (default) or uniform")->check(CLI::IsMember({"stratified", "uniform"}));
  make->add_option("--name", make_opts->name, "the suite's name (letters, digits, . _ -)")->required();
  make->add_option("--out", make_opts->out, "the suite file to write")->required();
  MTG_COMMAND({make, [make, make_opts]() -> int {
                        for (const CLI::Option* opt : make->get_options()) {
                          if (opt->count() > 0) make_opts->given.insert(opt->get_name());
                        }
                        return run_suite_make(*make_opts);
                      }});
  auto info_opts = options<SuiteInfoOptions>(commands);
  CLI::App* info = suite->add_subcommand("info", "What a suite holds: identity, draw, counts, spread, dataset, license");
  info->add_option("file", info_opts->file, "suite file")->required();
  info->add_flag("--json", info_opts->json, "print one JSON object");
  MTG_COMMAND({info, [info_opts] { return run_suite_info(*info_opts); }});
  auto verify_opts = options<SuiteVerifyOptions>(commands);
  CLI::App* verify = suite->add_subcommand("verify", "Check a suite's digest, the dataset here against it, and every goal");
  verify->add_option("file", verify_opts->file, "suite file")->required();
  verify->add_option("--data", verify_opts->data_dir, "dataset root (default: search order)");
  verify->add_option("--profile", verify_opts->profile, "scene profile (default replica_cad)");
  MTG_COMMAND({verify, [verify_opts] { return run_suite_verify(*verify_opts); }});
}

// mtg vlm ask
void add_vlm_commands(CLI::App& app, Commands& commands) {
  CLI::App* vlm = app.add_subcommand("vlm", "Talk to a model agent directly");
  vlm->require_subcommand(1);
  auto ask_opts = options<VlmAskOptions>(commands);
  CLI::App* vlm_ask = vlm->add_subcommand("ask", "Send one prompt (and images); check a key, a URL, the cache");
  vlm_ask->add_option("--agent", ask_opts->agent, "openai:<model>, anthropic:<model>, gemini:<model>, "
                      "openai-compatible:<url>:<model>")->required();
  vlm_ask->add_option("--text", ask_opts->text, "the prompt");
  vlm_ask->add_option("--image", ask_opts->images, "a PNG or JPEG file to attach (repeatable)");
  vlm_ask->add_option("--repeat", ask_opts->repeat, "send it this many times");
  vlm_ask->add_option("--parallel", ask_opts->parallel, "calls in flight at once");
  vlm_ask->add_option("--bus", ask_opts->bus_url, "share the rate governor on this LCM URL");
  vlm_ask->add_flag("--json", ask_opts->json, "one JSON line per call");
  mtg::vlm::add_vlm_options(*vlm_ask, ask_opts->vlm, false);
  MTG_COMMAND({vlm_ask, [ask_opts] { return run_vlm_ask(*ask_opts); }});
}

// mtg report | replay | rejudge
void add_result_commands(CLI::App& app, Commands& commands, [[maybe_unused]] char** argv) {
  auto report_opts = options<ReportOptions>(commands);
  CLI::App* report = app.add_subcommand("report", "Tables, failure taxonomy and Sankey of a run");
  report->add_option("run", report_opts->run, "run folder")->required();
  report->add_option("--html", report_opts->html, "write the HTML report here");
  report->add_flag("--json", report_opts->json, "print one JSON object");
  report->add_flag("--card", report_opts->card,
                   "also write the result card (card.md, card.json): suite, agents, SR/IP with intervals, cost, "
                   "provenance, how to cite");
  auto compare_opts = options<CompareOptions>(commands);
  CLI::App* compare = app.add_subcommand(
      "compare", "Paired comparison on the same tasks: the agents of a run, or an agent in two runs (B against A)");
  compare->add_option("run_a", compare_opts->run_a, "run folder (A, the baseline)")->required();
  compare->add_option("run_b", compare_opts->run_b, "second run folder (B); without it, the agents of A are compared");
  compare->add_option("--agent", compare_opts->agent, "compare this agent only");
  compare->add_option("--baseline", compare_opts->baseline, "one run: the agent the others are compared with (default: its first)");
  compare->add_flag("--json", compare_opts->json, "print one JSON object");
  MTG_COMMAND({compare, [compare_opts] { return run_compare(*compare_opts); }});
  auto leaderboard_opts = options<LeaderboardOptions>(commands);
  CLI::App* leaderboard = app.add_subcommand(
      "leaderboard", "Rank the agents of several runs per suite, with what paired tests can tell apart");
  leaderboard->add_option("runs", leaderboard_opts->runs, "run folders")->required();
  leaderboard->add_flag("--json", leaderboard_opts->json, "print one JSON object");
  leaderboard->add_option("--markdown", leaderboard_opts->markdown, "also write the boards as Markdown to this file");
  MTG_COMMAND({leaderboard, [leaderboard_opts] { return run_leaderboard(*leaderboard_opts); }});
  auto replay_opts = options<ReplayOptions>(commands);
  CLI::App* replay = app.add_subcommand("replay", "Re-drive the services from a run's recording; compare results");
  replay->add_option("run", replay_opts->run, "run folder")->required();
  replay->add_option("--out", replay_opts->out, "replay folder (default <run>/replay)");
  replay->add_option("--url", replay_opts->url, "LCM URL");
  replay->add_option("--parallel", replay_opts->parallel, "episodes at once (default 4)");
  auto rejudge_run = options<std::string>(commands);
  CLI::App* rejudge = app.add_subcommand("rejudge", "Re-score a run from its recorded actions (no agent)");
  rejudge->add_option("run", *rejudge_run, "run folder")->required();
  MTG_COMMAND({report, [report_opts] { return run_report(*report_opts); }});
  MTG_COMMAND({replay, [replay_opts, argv]() -> int {
                        if (replay_opts->url.empty()) {
                          if (const auto isolated = orchestrator::run_in_own_namespace(argv)) return *isolated;
                        }
                        return run_replay(*replay_opts);
                      }});
  MTG_COMMAND({rejudge, [rejudge_run] { return run_rejudge(*rejudge_run); }});
}

// mtg bench ... (what scripts/bench prints)
void add_bench_commands(CLI::App& app, Commands& commands) {
  CLI::App* bench = app.add_subcommand("bench", "Measure performance (used by scripts/bench)");
  bench->require_subcommand(1);
  auto bench_load = options<BenchSceneLoadOptions>(commands);
  CLI::App* bench_scene_load = bench->add_subcommand("scene-load", "Cold and warm scene loading");
  bench_scene_load->add_option("--scene", bench_load->scene, "scene name");
  bench_scene_load->add_option("--data", bench_load->data_dir, "dataset root");
  bench_scene_load->add_option("--repeat", bench_load->repeat, "warm repetitions");

  auto bench_graph = options<BenchSceneGraphOptions>(commands);
  CLI::App* bench_scene_graph = bench->add_subcommand("scene-graph", "Scene-graph build time per apartment");
  bench_scene_graph->add_option("--scene", bench_graph->scenes, "scene names (repeatable)");
  bench_scene_graph->add_option("--data", bench_graph->data_dir, "dataset root");
  bench_scene_graph->add_option("--repeat", bench_graph->repeat, "warm repetitions");

  auto bench_tasks = options<BenchTasksOptions>(commands);
  CLI::App* bench_tasks_cmd = bench->add_subcommand("tasks", "Task generation time per apartment and in all");
  bench_tasks_cmd->add_option("--scene", bench_tasks->scenes, "scene names (repeatable)");
  bench_tasks_cmd->add_option("--data", bench_tasks->data_dir, "dataset root");
  bench_tasks_cmd->add_option("--out", bench_tasks->out, "where the benchmark's task database goes");
  auto bench_runtime = options<BenchRuntimeOptions>(commands);
  CLI::App* bench_runtime_cmd = bench->add_subcommand("runtime", "Oracle episodes per second over the bus, per-step latency");
  bench_runtime_cmd->add_option("--scene", bench_runtime->scene, "scene name");
  bench_runtime_cmd->add_option("--data", bench_runtime->data_dir, "dataset root");
  bench_runtime_cmd->add_option("--work", bench_runtime->work, "scratch folder for tasks and runs (emptied first)");
  bench_runtime_cmd->add_option("--per-level", bench_runtime->per_level, "tasks per level (Levels 1-3)");
  bench_runtime_cmd->add_option("--parallel", bench_runtime->parallel, "episodes in flight (repeatable)");
  bench_runtime_cmd->add_option("--rounds", bench_runtime->rounds, "times each parallelism runs, alternating (default 3)")
      ->check(CLI::PositiveNumber);

  auto bench_render = options<BenchRenderOptions>(commands);
  CLI::App* bench_render_cmd = bench->add_subcommand("render", "Renderer: ms per annotated observation, episodes with images");
  bench_render_cmd->add_option("--scene", bench_render->scene, "scene name");
  bench_render_cmd->add_option("--data", bench_render->data_dir, "dataset root");
  bench_render_cmd->add_option("--rounds", bench_render->rounds, "passes over every navigable platform");
  bench_render_cmd->add_option("--episodes", bench_render->episodes, "oracle episodes rendered end to end");
  auto bench_pool = options<BenchPoolOptions>(commands);
  CLI::App* bench_pool_cmd =
      bench->add_subcommand("pool", "Rendered episodes over the bus with pools of 1, 2, ... renderers");
  bench_pool_cmd->add_option("--scene", bench_pool->scene, "scene name");
  bench_pool_cmd->add_option("--data", bench_pool->data_dir, "dataset root");
  bench_pool_cmd->add_option("--work", bench_pool->work, "scratch folder for tasks and runs (emptied first)");
  bench_pool_cmd->add_option("--per-level", bench_pool->per_level, "tasks per level (Levels 1-3; default 10)");
  bench_pool_cmd->add_option("--parallel", bench_pool->parallel, "episodes in flight (default 4)");
  bench_pool_cmd->add_option("--renderers", bench_pool->renderers, "pool sizes compared (repeatable; default 1 2)")
      ->check(CLI::Range(1, 256));
  bench_pool_cmd->add_option("--rounds", bench_pool->rounds, "times each pool runs, alternating (default 2)")
      ->check(CLI::Range(1, 100));
  MTG_COMMAND({bench_pool_cmd, [bench_pool] { return run_bench_pool(*bench_pool); }});
  auto bench_soak = options<BenchSoakOptions>(commands);
  CLI::App* bench_soak_cmd = bench->add_subcommand("soak", "A long run: every process's memory as episodes go by, episodes/s, bytes recorded");
  bench_soak_cmd->add_option("--episodes", bench_soak->episodes, "episodes in all (default 1,000,000)");
  bench_soak_cmd->add_option("--scene", bench_soak->scene, "scene whose tasks (Levels 1-4) are generated");
  bench_soak_cmd->add_option("--tasks", bench_soak->tasks, "a task database to run instead");
  bench_soak_cmd->add_option("--data", bench_soak->data_dir, "dataset root");
  bench_soak_cmd->add_option("--work", bench_soak->work, "scratch folder for tasks and the run (emptied first)");
  bench_soak_cmd->add_option("--agent", bench_soak->agents, "agents (repeatable; default oracle and random)");
  bench_soak_cmd->add_option("--levels", bench_soak->levels, "levels (default 1,2,3,4)");
  bench_soak_cmd->add_option("--parallel", bench_soak->parallel, "episodes in flight (default 4)");
  bench_soak_cmd->add_flag("--render", bench_soak->render, "observations carry images");
  bench_soak_cmd->add_option("--every", bench_soak->every_s, "seconds between rows (default 60)");
  bench_soak_cmd->add_option("--json", bench_soak->json, "also write every sample to this file");
  MTG_COMMAND({bench_soak_cmd, [bench_soak] { return run_bench_soak(*bench_soak); }});
  MTG_COMMAND({bench_scene_load, [bench_load] { return run_bench_scene_load(*bench_load); }});
  MTG_COMMAND({bench_tasks_cmd, [bench_tasks] { return run_bench_tasks(*bench_tasks); }});
  MTG_COMMAND({bench_scene_graph, [bench_graph] { return run_bench_scene_graph(*bench_graph); }});
  MTG_COMMAND({bench_runtime_cmd, [bench_runtime] { return run_bench_runtime(*bench_runtime); }});
  MTG_COMMAND({bench_render_cmd, [bench_render] { return run_bench_render(*bench_render); }});
}

// mtg view | play
void add_view_commands(CLI::App& app, Commands& commands, [[maybe_unused]] char** argv) {
  auto view_opts = options<ViewOptions>(commands);
  CLI::App* view = app.add_subcommand("view", "Look inside runs in the browser: results, Sankey, every step");
  view->add_option("runs", view_opts->runs, "run folders")->required();
  view->add_option("--host", view_opts->host, "address to listen on (default 127.0.0.1: this machine only)");
  view->add_option("--port", view_opts->port, "port (default 8770; 0 = any free port)");
  MTG_COMMAND({view, [view_opts] { return run_view(*view_opts); }});

  auto export_opts = options<ExportOptions>(commands);
  CLI::App* exp = app.add_subcommand("export", "Write runs as a static site (no server, opens from file://, offline)");
  exp->add_option("runs", export_opts->runs, "run folders")->required();
  exp->add_option("--out", export_opts->out, "a new or empty folder")->required();
  MTG_COMMAND({exp, [export_opts] { return run_export(*export_opts); }});

  auto play_opts = options<PlayOptions>(commands);
  CLI::App* play = app.add_subcommand("play", "Play episodes yourself in the browser (the human agent)");
  CLI::Option* play_tasks = play->add_option("--tasks", play_opts->tasks, "task database (tasks.sqlite)");
  play->add_option("--suite", play_opts->suite, "a suite file (mtg suite make): play its tasks")->excludes(play_tasks);
  play->add_option("--scene", play_opts->scenes, "only tasks of this scene (repeat for several)");
  play->add_option("--levels", play_opts->levels, "levels to play (default 1,2,3)");
  play->add_option("--limit", play_opts->limit, "tasks per scene and level (default 1)");
  play->add_option("--draw", play_opts->draw, "how --limit draws: stratified (default) or uniform")
      ->check(CLI::IsMember({"stratified", "uniform"}));
  play->add_option("--seed", play_opts->seed, "run seed (default 0)");
  play->add_option("--out", play_opts->out, "run folder (default ./play; the same command resumes)");
  play->add_option("--data", play_opts->data_dir, "dataset root (default: search order)");
  play->add_option("--profile", play_opts->profile, "scene profile (default replica_cad)");
  play->add_option("--bus", play_opts->url, "LCM URL (default: the host-local bus)");
  play->add_option("--step-limit", play_opts->step_limit, "steps per episode, at least (default 15)");
  play->add_option("--lookalike-aid", play_opts->lookalike_aid,
                   "how look-alikes are told apart: both (default), words or image (as mtg run)")
      ->check(CLI::IsMember({"both", "words", "image"}));
  play->add_option("--host", play_opts->host, "address of the play page (default 127.0.0.1)");
  play->add_option("--port", play_opts->port, "port of the play page (default 8780)");
  MTG_COMMAND({play, [play_opts, argv]() -> int {
                        // Like mtg run, a bus of its own; the page is relayed from the host's
                        // network into the namespace (page_relay.h).
                        if (play_opts->url.empty() && !orchestrator::inside_run_namespace()) {
                          auto page = std::make_unique<orchestrator::PageRelay>(play_opts->host, play_opts->port);
                          if (const auto isolated = orchestrator::run_in_own_namespace(argv, page.get())) return *isolated;
                        }
                        return run_play(*play_opts);
                      }});

  auto audit_opts = options<AuditCommandOptions>(commands);
  CLI::App* audit = app.add_subcommand("audit", "Judge sampled tasks from what the agent sees, in the browser (Table 2)");
  audit->require_subcommand(0, 1);
  CLI::Option* audit_tasks = audit->add_option("--tasks", audit_opts->tasks, "task database (tasks.sqlite)");
  audit->add_option("--suite", audit_opts->tasks, "a suite file (mtg suite make): audit tasks drawn from it")
      ->excludes(audit_tasks);
  audit->add_option("--scene", audit_opts->scene, "only tasks of this scene");
  audit->add_option("--per-level", audit_opts->per_level, "tasks drawn per level (default 10)");
  audit->add_option("--seed", audit_opts->seed, "seed of the draw (default 0)");
  audit->add_option("--out", audit_opts->out, "the audit's folder (answers in DIR/audit.sqlite; the same command resumes)");
  audit->add_option("--data", audit_opts->data_dir, "dataset root (default: search order)");
  audit->add_option("--profile", audit_opts->profile, "scene profile (default replica_cad)");
  audit->add_option("--width", audit_opts->width, "image width (default 640)");
  audit->add_option("--height", audit_opts->height, "image height (default 480)");
  audit->add_flag("--names", audit_opts->names, "name objects in the text, as text-only runs do");
  audit->add_option("--lookalike-aid", audit_opts->lookalike_aid,
                    "what the page gives of look-alikes: both (default), words (no close-ups) or image (close-ups, "
                    "the text naming them by close-up)")
      ->check(CLI::IsMember({"both", "words", "image"}));
  audit->add_option("--host", audit_opts->host, "address of the page (default 127.0.0.1)");
  audit->add_option("--port", audit_opts->port, "port of the page (default 8790; 0 = any free port)");
  audit->add_flag("--prepare-only", audit_opts->prepare_only, "make the audit's folder and exit");
  audit->add_option("--rater", audit_opts->rater, "who answers (default rater): several people judge the same draw");
  auto audit_report_opts = options<AuditReportOptions>(commands);
  CLI::App* audit_report = audit->add_subcommand("report", "Validity per level (95 % interval) and identification accuracy");
  audit_report->add_option("dir", audit_report_opts->dir, "the audit's folder")->required();
  audit_report->add_flag("--json", audit_report_opts->json, "print one JSON object");
  MTG_COMMAND({audit_report, [audit_report_opts] { return run_audit_report(*audit_report_opts); }});
  auto sights_opts = options<SightsDrawOptions>(commands);
  CLI::App* sights = audit->add_subcommand(
      "sights", "Objects drawn from platform views with an arrow each, for people to say whether they see and can name them");
  sights->require_subcommand(0, 1);
  sights->add_option("--scene", sights_opts->scenes, "scene (repeat for several)");
  sights->add_option("--data", sights_opts->data_dir, "dataset root (default: search order)");
  sights->add_option("--profile", sights_opts->profile, "scene profile (default replica_cad)");
  sights->add_option("--count", sights_opts->count, "objects drawn (default 200)");
  sights->add_option("--seed", sights_opts->seed, "seed of the draw (default 0)");
  sights->add_option("--out", sights_opts->out, "folder for images/, sights.json and labels/ (what raters get)");
  sights->add_option("--key", sights_opts->key,
                     "where the answers (objects, nouns, pixels) go, outside the raters' folder (default <out>-key.json)");
  auto sights_report_opts = options<SightsReportOptions>(commands);
  CLI::App* sights_report =
      sights->add_subcommand("report", "The visibility rule against the answers in DIR/labels: agreement, best thresholds, kappa");
  sights_report->add_option("dir", sights_report_opts->dir, "the draw's folder")->required();
  sights_report->add_flag("--json", sights_report_opts->json, "print one JSON object");
  sights_report->add_option("--key", sights_report_opts->key, "the draw's key (default <dir>-key.json)");
  MTG_COMMAND({sights_report, [sights_report_opts] { return run_sights_report(*sights_report_opts); }});
  MTG_COMMAND({sights, [sights_opts] { return run_sights_draw(*sights_opts); }});
  MTG_COMMAND({audit, [audit_opts] {
                        if (audit_opts->tasks.empty() || audit_opts->out.empty()) {
                          throw mtg::Error("mtg audit: --tasks <task database> and --out <folder> are required");
                        }
                        return run_audit(*audit_opts);
                      },
                      true});
}

}  // namespace
}  // namespace mtg::cli

// jemalloc, the allocator every program links (CMakeLists.txt), reads its settings from this
// symbol. Task generation frees each scene's working memory in bursts: handing unused pages back
// after one second instead of jemalloc's ten keeps the peak of `mtg tasks` over the three shipped
// apartments about a tenth lower, at no measurable cost in time (docs/build.md).
extern "C" {
const char* malloc_conf = "dirty_decay_ms:1000";
}

int main(int argc, char** argv) {
  CLI::App app{"ManiTaskGen-LCM: scene graphs, task generation and closed-loop VLM benchmarks"};
  app.require_subcommand(1);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "debug, info, warn, error or off");
  mtg::cli::Commands commands;
  mtg::cli::add_scene_commands(app, commands);
  mtg::cli::add_render_commands(app, commands);
  mtg::cli::add_task_commands(app, commands);
  mtg::cli::add_run_commands(app, commands, argv);
  mtg::cli::add_suite_commands(app, commands);
  mtg::cli::add_vlm_commands(app, commands);
  mtg::cli::add_result_commands(app, commands, argv);
  mtg::cli::add_bench_commands(app, commands);
  mtg::cli::add_view_commands(app, commands, argv);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
#ifdef MTG_CLI_FRONT
  (void)commands;
  return mtg::cli::run_beside(argv);
#else
  try {
    const bool level_given = app.get_option("--log-level")->count() > 0;
    for (const mtg::cli::Command& c : commands.list) {
      if (!c.app->parsed()) continue;
      mtg::log::set_level(mtg::log::parse_level(c.quiet_by_default && !level_given ? "warn" : log_level));
      return c.run();
    }
    mtg::log::set_level(mtg::log::parse_level(log_level));
  } catch (const mtg::Error& e) {
    std::cerr << mtg::cli::where(app, e.what()) << '\n';
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << mtg::cli::where(app, e.code().message() + ": " + e.path1().string()) << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << mtg::cli::where(app, std::string("unexpected failure: ") + e.what()) << '\n';
    return 1;
  }
  return 0;
#endif
}
