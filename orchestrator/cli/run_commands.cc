#include "orchestrator/cli/run_commands.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <tuple>

#include "agents/builtin/policies.h"
#include "agents/vlm/model_setup.h"
#include "bus/authenticator.h"
#include "bus/process/identity.h"
#include "bus/recording_ref.h"
#include "bus/url.h"
#include "core/scene/dataset.h"
#include "core/scene/dataset_fingerprint.h"
#include "core/util/build_info.h"
#include "core/util/host_name.h"
#include "core/tasks/generator.h"
#include "core/tasks/draw.h"
#include "core/tasks/suite.h"
#include "core/tasks/task_db.h"
#include "core/util/file_bytes.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "orchestrator/remote/recordings_place.h"
#include "orchestrator/remote/slurm_workers.h"
#include "orchestrator/remote/tcp_hub.h"
#include "orchestrator/report/card.h"
#include "orchestrator/report/compare.h"
#include "orchestrator/run/goal_check.h"
#include "orchestrator/run/provenance.h"
#include "orchestrator/report/report.h"
#include "orchestrator/run/rejudge.h"
#include "core/graph/scene_cache.h"
#include "orchestrator/run/run_estimate.h"
#include "orchestrator/run/results_db.h"
#include "orchestrator/run/run_engine.h"
#include "orchestrator/run/page_relay.h"
#include "orchestrator/run/run_folder_check.h"
#include "orchestrator/run/run_lock.h"
#include "orchestrator/run/run_namespace.h"
#include "orchestrator/run/run_plan.h"

namespace mtg::cli {
namespace {

namespace fs = std::filesystem;
using orchestrator::RunPlan;

std::map<std::string, tasks::Task> by_id(std::vector<tasks::Task> all) {
  std::map<std::string, tasks::Task> out;
  for (auto& t : all) {
    std::string id = t.id;
    out.emplace(std::move(id), std::move(t));
  }
  return out;
}

std::map<std::string, tasks::Task> load_tasks(const std::string& db) { return by_id(tasks::read_tasks(db)); }

// What every host's adapters must share (limits, cache policy); files and keys are host-local.
vlm::VlmOptions run_wide(vlm::VlmOptions o) {
  o.config_file.clear();
  o.cache_file.clear();
  o.key_file.clear();
  o.prompts_dir.clear();
  o.prices_file.clear();
  o.base_url.clear();
  return o;
}

// What the run's tasks are and how spread they are (plan.json's provenance, draw_record): "" for
// a plan from before draws were recorded.
std::string draw_line(const nlohmann::json& provenance) {
  if (!provenance.is_object() || !provenance.contains("draw")) return "";
  const nlohmann::json& d = provenance["draw"];
  std::string line = "tasks: ";
  const std::string kind = d.value("kind", std::string("?"));
  if (kind == "suite" && provenance.contains("suite")) {
    line += "suite " + provenance["suite"].value("id", std::string("?"));
  } else if (kind == "all") {
    line += "every task of the set";
  } else {
    line += kind + " draw of " + std::to_string(d.value("limit", 0)) + " per scene and level";
  }
  std::string spread;
  const nlohmann::json levels = d.value("spread", nlohmann::json::object());
  for (const auto& [level, sp] : levels.items()) {
    char part[160];
    std::snprintf(part, sizeof part, "%sL%s %.0f %% (%s)", spread.empty() ? "" : ", ", level.c_str(),
                  100.0 * sp.value("biggest_share", 0.0), sp.value("biggest", std::string()).c_str());
    spread += part;
  }
  if (!spread.empty()) line += "; share of the biggest stratum (source platform; L4 outcome kind): " + spread;
  return line;
}

void print_summary(const orchestrator::RunSummary& s, const fs::path& dir, const nlohmann::json& report, bool remote) {
  std::printf("run %s: %lld episodes planned, %lld done now (%lld before), %lld given up, %lld retries, "
              "%d restarts, %.1f s\n",
              dir.filename().c_str(), static_cast<long long>(s.planned), static_cast<long long>(s.completed),
              static_cast<long long>(s.already_done), static_cast<long long>(s.errors),
              static_cast<long long>(s.retries), s.restarts, s.seconds);
  if (s.completed > 0 && s.seconds > 0 && s.cpu_seconds > 0) {
    // Start-up included (scenes, GPU upload): the figure of a whole invocation. With workers the
    // episodes ran elsewhere: their CPU is not in it, so no per-CPU-second figure is claimed.
    if (remote) {
      std::printf("  %.2f episodes/s; this coordinator used %.1f CPU-s (the workers' CPU is on their hosts, not "
                  "counted here)\n",
                  static_cast<double>(s.completed) / s.seconds, s.cpu_seconds);
    } else {
      std::printf("  %.2f episodes/s, %.3f episodes per CPU-second (%.1f CPU-s: mtg and the processes it ran here)\n",
                  static_cast<double>(s.completed) / s.seconds, static_cast<double>(s.completed) / s.cpu_seconds,
                  s.cpu_seconds);
    }
  }
  std::printf("  SR %s %%  IP %s  over %lld scored episodes (95 %% intervals)\n",
              orchestrator::with_interval(report, "sr").c_str(), orchestrator::with_interval(report, "ip").c_str(),
              static_cast<long long>(report["scored"].get<std::int64_t>()));
  for (const auto& [agent, a] : report["by_agent"].items()) {
    std::printf("  %-12s SR %s %%  IP %s  (%lld episodes)\n", agent.c_str(), orchestrator::with_interval(a, "sr").c_str(),
                orchestrator::with_interval(a, "ip").c_str(), static_cast<long long>(a["episodes"].get<std::int64_t>()));
  }
  if (report.contains("usage")) {
    for (const auto& [agent, u] : report["usage"].items()) {
      char spent[96];
      if (u.value("price_known", true)) {
        std::snprintf(spent, sizeof spent, "$%.4f list price, $%.4f spent", u["cost_usd"].get<double>(),
                      u["spent_usd"].get<double>());
      } else {  // an endpoint of one's own: the table's figure is a guess, nothing is spent
        std::snprintf(spent, sizeof spent, "$%.4f at list price (a guess for this endpoint)", u["cost_usd"].get<double>());
      }
      std::printf("  %-12s %lld calls (%lld from the cache), %lld+%lld tokens, %lld images, %s\n", agent.c_str(),
                  static_cast<long long>(u["calls"].get<std::int64_t>()),
                  static_cast<long long>(u["cache_hits"].get<std::int64_t>()),
                  static_cast<long long>(u["input_tokens"].get<std::int64_t>()),
                  static_cast<long long>(u["output_tokens"].get<std::int64_t>()),
                  static_cast<long long>(u["images"].get<std::int64_t>()), spent);
    }
  }
  std::printf("  results     %s\n", (dir / "results.sqlite").c_str());
  const auto refs = bus::read_recording_refs(dir / "results.sqlite");
  if (refs.empty()) {
    std::printf("  recording   %s/bus-*.lcmlog\n", dir.c_str());
    if (fs::exists(dir / "episodes")) std::printf("  episodes    %s/episodes/ (each attempt's recording from its worker)\n", dir.c_str());
  } else {
    // Kept where they were made (docs/multihost.md): say where, and how to bring them here.
    std::size_t on_workers = 0;
    for (const auto& r : refs) on_workers += r.shared ? 0 : 1;
    const fs::path first = bus::resolve(refs.front(), dir);
    std::printf("  recordings  %zu referenced by results.sqlite", refs.size());
    if (on_workers > 0) {
      std::printf(", %zu kept on the workers (`mtg gather %s` brings them here)\n", on_workers, dir.c_str());
    } else {
      std::printf(", in %s/\n", first.parent_path().c_str());
    }
  }
  std::printf("  report      %s (+ report.png, report.json)\n", (dir / "report.html").c_str());
  std::printf("  logs        %s/logs/\n", dir.c_str());
}

// Whether observations name objects. The paper's action space numbers objects only, for agents
// that see them; an agent without images, or a task set whose look-alike rule is "name" (its
// texts say "cup 01", which no image shows), needs the names (docs/episode.md).
// `generator_config` is asked for only when it decides (auto, with images).
bool object_names_for(const std::string& option, bool render, const std::function<nlohmann::json()>& generator_config) {
  if (option == "on") return true;
  if (option == "off") return false;
  if (option != "auto") throw Error("--object-names is on, off or auto, not '" + option + "'");
  if (!render) return true;
  const nlohmann::json config = generator_config();
  return config.is_object() && config.value("ambiguity", "") == "name";
}

// How look-alikes are told apart; "image" alone needs the images that carry the close-ups.
episode::LookalikeAid lookalike_aid_for(const std::string& option, bool render) {
  const episode::LookalikeAid aid = episode::lookalike_aid_from_string(option, "--lookalike-aid");
  if (aid == episode::LookalikeAid::kImage && !render) {
    throw Error("--lookalike-aid image needs images (--render, or a model agent without --no-render)");
  }
  return aid;
}

// The largest observation image: every image of an observation travels in one bus message,
// which must fit the 4 MB receive buffer with room to spare (docs/bus.md).
constexpr long kMaxImagePixels = 1280L * 1024L;

std::pair<int, int> parse_image_size(const std::string& text) {
  const auto x = text.find('x');
  int w = 0, h = 0;
  try {
    if (x == std::string::npos) throw std::invalid_argument("no x");
    std::size_t used_w = 0, used_h = 0;
    w = std::stoi(text.substr(0, x), &used_w);
    h = std::stoi(text.substr(x + 1), &used_h);
    if (used_w != x || used_h != text.size() - x - 1) throw std::invalid_argument("trailing characters");
  } catch (const std::exception&) {
    throw Error("--image-size must be WIDTHxHEIGHT, e.g. 640x480, not '" + text + "'");
  }
  if (w < 16 || h < 16 || static_cast<long>(w) * h > kMaxImagePixels) {
    throw Error("--image-size " + text + " is outside what an observation may carry: at least 16x16 and at most " +
                std::to_string(kMaxImagePixels) + " pixels (e.g. 1280x1024)");
  }
  return {w, h};
}

// Every agent is known, and a model agent's key, settings, prompts, prices and cache are usable:
// one clear line now rather than adapters that never become ready. With workers the keys and
// files are on their hosts; each worker checks its own when it joins. An estimate needs no key.
void check_agents(const std::vector<std::string>& agents, const vlm::VlmOptions& vlm, bool remote, bool estimate_only) {
  for (const std::string& spec : agents) {
    if (vlm::is_model_spec(spec)) {
      // An estimate calls no model: it needs the spec and the price table, not a key.
      if (estimate_only) {
        (void)vlm::parse_model_spec(spec);
      } else if (!remote) {
        (void)vlm::ModelSetup::make(spec, vlm.resolve());
      }
    } else if (spec == agents::kHumanAgent) {
      if (remote) throw Error("the human agent plays on this machine (mtg play), not on workers");
    } else if (!agents::is_builtin_agent(spec)) {
      throw Error("unknown agent '" + spec + "' (oracle, random, replay:<run>, script:<file>, human, "
                  "openai:<model>, anthropic:<model>, gemini:<model>, openai-compatible:<url>:<model>)");
    } else if (!remote && spec.rfind("script:", 0) == 0) {
      (void)agents::make_builtin_policy(spec);  // reads the file: a missing or bad one is named now
    } else if (!remote && spec.rfind("replay:", 0) == 0 && !fs::is_directory(spec.substr(7))) {
      throw Error("agent " + spec + ": " + spec.substr(7) + " is not a run folder");
    }
  }
}

// Where a run with --suite keeps its copy of the suite, which is its task set from then on: the
// folder needs nothing outside it to resume, rejudge or view.
constexpr const char* kSuiteCopy = "suite.json";

// A new run's plan from the options (the episodes are laid out by make_plan). With a suite, its
// tasks are read from `suite_file` until the run folder holds its copy.
RunPlan plan_from_options(const RunOptions& o, const fs::path& dir, const tasks::Suite* suite) {
  if (o.tasks.empty() && suite == nullptr) throw Error("--tasks <tasks.sqlite> or --suite <suite file> is required");
  if (suite != nullptr) {
    std::vector<std::string> drawn;
    for (const char* option : {"--limit", "--levels", "--scene", "--draw"}) {
      if (o.given.count(option)) drawn.push_back(option);
    }
    if (!drawn.empty()) {
      std::string names;
      for (const auto& d : drawn) names += (names.empty() ? "" : ", ") + d;
      throw Error("a suite runs exactly its tasks (" + o.suite + "); " + names + (drawn.size() == 1 ? " goes" : " go") +
                  " with a task set (--tasks tasks.sqlite)");
    }
  }
  if (o.given.count("--parallel") && o.parallel < 1) throw Error("--parallel must be at least 1, not " + std::to_string(o.parallel));
  if (o.limit < 0) throw Error("--limit must be 0 (every task) or more, not " + std::to_string(o.limit));
  if (o.step_limit < 1) throw Error("--step-limit must be at least 1, not " + std::to_string(o.step_limit));
  if (o.render && o.no_render) throw Error("--render and --no-render contradict each other");
  RunPlan plan;
  plan.run_id = orchestrator::new_run_id(dir.filename().string());
  const std::string source = suite != nullptr ? o.suite : o.tasks;
  plan.tasks_db = suite != nullptr ? (dir / kSuiteCopy).string() : fs::absolute(o.tasks).lexically_normal().string();
  plan.agents = o.agents;
  plan.scenes = {o.scenes.begin(), o.scenes.end()};
  plan.levels = tasks::parse_levels(o.levels);
  if (suite != nullptr) {
    plan.levels.clear();
    for (const auto& t : suite->tasks) plan.levels.insert(t.level);
  }
  plan.limit = suite != nullptr ? 0 : o.limit;  // a suite is its tasks, all of them (mtg play passes its default)
  plan.draw = tasks::draw_kind_from_string(o.draw);
  plan.repeat = o.repeat;
  plan.seed = o.seed;
  // With workers their capacities decide, unless --parallel caps the whole run.
  plan.parallel = o.given.count("--parallel") ? o.parallel : (o.remote ? 0 : 4);
  plan.step_limit = o.step_limit;
  // Built-in agents read only the text; images are for model agents (and people) unless asked for.
  const bool model_agent = std::any_of(o.agents.begin(), o.agents.end(),
                                       [](const std::string& a) { return !agents::is_builtin_agent(a); });
  plan.render = o.render || (model_agent && !o.no_render);
  std::tie(plan.image_width, plan.image_height) = parse_image_size(o.image_size);
  plan.image_encoding = o.image_encoding;
  plan.object_names = object_names_for(o.object_names, plan.render, [&] {
    return suite != nullptr ? suite->generator.value("config", nlohmann::json()) : tasks::read_generator_config(source);
  });
  plan.lookalike_aid = lookalike_aid_for(o.lookalike_aid, plan.render);
  const std::string task_format = suite != nullptr ? suite->generator.value("task_format", std::string())
                                                   : tasks::read_task_set_meta(source, "generator_version").value_or(std::string());
  plan.numbering = tasks::numbering_of_format(task_format);
  plan.platform_rules = tasks::platform_rules_of_format(task_format);
  // A model call may wait minutes for rate limits and retries before the next message.
  plan.episode_timeout_s = o.episode_timeout_s > 0 ? o.episode_timeout_s : (model_agent ? 900.0 : 60.0);
  plan.data_dir = o.data_dir;
  plan.profile = o.profile;
  if (o.given.count("--slurm") && o.url.empty()) {
    // Cluster networks rarely carry multicast: the run brings its own hub (started in run_run).
    const std::string host = o.hub_host.empty() ? process::host_name() : o.hub_host;
    // The port is the one given, else the first free one, chosen when the hub starts (run_run).
    plan.bus_url = orchestrator::remote::hub_url(host, o.hub_port);
  } else {
    plan.bus_url = bus::normalize_url(o.url.empty() ? bus::default_url() : o.url);
  }
  plan.remote = o.remote;
  if (o.given.count("--recordings") && !o.remote && o.given.count("--slurm") == 0) {
    throw Error("--recordings goes with --remote or --slurm (a run on one machine records its own bus)");
  }
  plan.recordings = orchestrator::remote::parse_recordings_place(o.recordings).to_string();
  plan.allow_data_mismatch = o.allow_data_mismatch;
  return plan;
}

// The task set's fingerprints of the scenes the plan runs.
std::map<std::string, scene::DatasetFingerprint> fingerprints_of(const RunPlan& plan,
                                                                 std::map<std::string, scene::DatasetFingerprint> all,
                                                                 const std::map<std::string, tasks::Task>& tasks) {
  std::set<std::string> scenes;
  for (const auto& e : plan.episodes) scenes.insert(tasks.at(e.task_id).scene);
  std::map<std::string, scene::DatasetFingerprint> out;
  for (auto& [scene, f] : all) {
    if (scenes.count(scene) != 0) out.emplace(scene, std::move(f));
  }
  return out;
}

// How the run's tasks were chosen, for its provenance and report: the draw, and how spread the
// tasks are (each level's biggest stratum and its share, tasks/draw.h).
nlohmann::json draw_record(const RunPlan& plan, const std::map<std::string, tasks::Task>& tasks, bool from_suite) {
  std::set<std::string> planned;
  for (const auto& e : plan.episodes) planned.insert(e.task_id);
  std::vector<const tasks::Task*> list;
  for (const auto& id : planned) list.push_back(&tasks.at(id));
  const std::string kind = from_suite ? "suite" : (plan.limit > 0 ? tasks::to_string(plan.draw) : "all");
  return {{"kind", kind}, {"limit", plan.limit}, {"seed", plan.seed}, {"spread", tasks::to_json(tasks::spread_of(list))}};
}

// A run on this machine refuses a dataset other than the task set's (a missing mesh would turn
// the oracle's tasks into failures without a word); workers check their own as they join.
void check_dataset(const RunPlan& plan, const std::string& task_source,
                   const std::map<std::string, scene::DatasetFingerprint>& expected) {
  const fs::path root = scene::resolve_data_root(plan.data_dir);
  const std::string diff = scene::first_difference(expected, root);
  if (diff.empty()) return;
  const std::string what = "the dataset at " + root.string() + " is not the one " + task_source + " was made from (" + diff + ")";
  if (!plan.allow_data_mismatch) throw Error(what + "; use that dataset (--data) or --allow-data-mismatch");
  log::warn(what + "; going on (--allow-data-mismatch)");
}

// Every planned task's goal resolves here before anything is written (goal_check.h). Without the
// dataset here (a coordinator whose workers hold it) the workers check each episode as it starts.
void check_goals(const RunPlan& plan, const std::string& task_source, const std::map<std::string, tasks::Task>& tasks,
                 graph::SceneCache& scenes) {
  std::set<std::string> planned;
  for (const auto& e : plan.episodes) planned.insert(e.task_id);
  std::vector<const tasks::Task*> list;
  for (const std::string& id : planned) list.push_back(&tasks.at(id));
  orchestrator::check_goals(list, plan.profile, plan.platform_rules, plan.data_dir, task_source,
                            plan.remote ? orchestrator::MissingScene::kSkip : orchestrator::MissingScene::kFail, &scenes);
}

// A resume runs the plan on disk: options that would change what it evaluates are refused, with
// the names of those that differ.
void check_resume(const RunPlan& plan, const RunOptions& o, const fs::path& dir, const tasks::Suite* suite) {
  if (suite != nullptr) {
    const bool same = tasks::is_suite_file(plan.tasks_db) && tasks::read_suite(plan.tasks_db).digest == suite->digest;
    if (!same) throw Error(dir.string() + " holds a run of " + plan.tasks_db + ", not of suite " + suite->id() + "; use another --out");
  }
  if (!o.tasks.empty() && fs::absolute(o.tasks).lexically_normal().string() != plan.tasks_db) {
    throw Error(dir.string() + " holds a run of " + plan.tasks_db + "; use another --out for " + o.tasks);
  }
  if (!o.agents.empty() && o.agents != plan.agents) throw Error(dir.string() + " holds a run of other agents; use another --out");
  std::vector<std::string> changed;
  auto differs = [&](const char* option, bool different) {
    if (o.given.count(option) && different) changed.push_back(option);
  };
  differs("--levels", tasks::parse_levels(o.levels) != plan.levels);
  differs("--limit", o.limit != plan.limit);
  differs("--draw", tasks::draw_kind_from_string(o.draw) != plan.draw);
  differs("--repeat", o.repeat != plan.repeat);
  differs("--seed", o.seed != plan.seed);
  differs("--scene", std::set<std::string>(o.scenes.begin(), o.scenes.end()) != plan.scenes);
  differs("--step-limit", o.step_limit != plan.step_limit);
  differs("--render", !plan.render);
  differs("--no-render", plan.render);
  differs("--image-size", parse_image_size(o.image_size) != std::make_pair(plan.image_width, plan.image_height));
  differs("--image-encoding", o.image_encoding != plan.image_encoding);
  differs("--object-names", object_names_for(o.object_names, plan.render,
                                             [&] { return tasks::read_generator_config(plan.tasks_db); }) != plan.object_names);
  differs("--lookalike-aid", lookalike_aid_for(o.lookalike_aid, plan.render) != plan.lookalike_aid);
  differs("--data", o.data_dir != plan.data_dir);
  differs("--profile", o.profile != plan.profile);
  differs("--parallel", o.parallel != plan.parallel);
  differs("--recordings", orchestrator::remote::parse_recordings_place(o.recordings).to_string() != plan.recordings);
  if (changed.empty()) return;
  std::string names;
  for (const auto& c : changed) names += (names.empty() ? "" : ", ") + c;
  throw Error(dir.string() + " holds a run planned with other " + names +
              "; resume it without them (the plan is in plan.json) or use another --out");
}

// The key of a Slurm run's shared bus: the one given, else a fresh secret in the run folder
// (which the nodes see at the same path), kept for a resume.
std::string slurm_bus_key(const RunOptions& o, const fs::path& dir) {
  if (!o.remote_options.bus_key.empty() || std::getenv("MTG_BUS_KEY") != nullptr) {
    return fs::absolute(bus::shared_bus_key_file(o.remote_options.bus_key)).string();
  }
  const fs::path key = dir / "bus.key";
  bus::create_key_file(key);
  return key.string();
}

// What a Slurm run starts beside the engine, stopped (hub) and cancelled (job array) when the
// run ends, is interrupted or fails.
struct SlurmRun {
  std::unique_ptr<orchestrator::remote::HubProcess> hub;
  std::unique_ptr<orchestrator::remote::SlurmWorkers> workers;  // cancelled before the hub stops
};

// The run's own hub (a --slurm run without --bus) on --hub-port, else on the first free port;
// the plan's URL follows it. A resumed run may get another port than it was planned with: its
// old hub and workers went with the old coordinator, and the new array is given the new URL.
std::unique_ptr<orchestrator::remote::HubProcess> start_run_hub(const RunOptions& o, RunPlan& plan,
                                                                const fs::path& dir) {
  namespace remote_ns = orchestrator::remote;
  const auto planned = bus::parse_tcpq(plan.bus_url);
  if (!planned) {
    throw Error(dir.string() + " was planned on the bus " + plan.bus_url + ", not a hub; resume it with --bus " +
                plan.bus_url);
  }
  // The hub's log beside the run: kept even when the hub fails to start, to say why.
  fs::create_directories(dir / "slurm");
  auto hub = std::make_unique<remote_ns::HubProcess>(
      o.given.count("--hub-port") ? o.hub_port : remote_ns::HubProcess::kAnyPort, (dir / "slurm" / "hub.log").string());
  plan.bus_url = remote_ns::hub_url(planned->host, hub->port());
  std::printf("LCM hub for the workers: %s\n", plan.bus_url.c_str());
  return hub;
}

std::unique_ptr<orchestrator::remote::SlurmWorkers> submit_slurm_workers(const RunOptions& o, const RunPlan& plan,
                                                                         const fs::path& dir,
                                                                         orchestrator::remote::RemoteOptions& remote) {
  namespace remote_ns = orchestrator::remote;
  const fs::path slurm_dir = dir / "slurm";
  fs::create_directories(slurm_dir);
  remote.bus_key = slurm_bus_key(o, dir);
  remote_ns::SlurmRequest request;
  request.sbatch_options = o.slurm;
  request.workers = o.slurm_workers;
  request.capacity = o.worker_capacity;
  request.mtg_binary = fs::read_symlink("/proc/self/exe").string();
  request.bus_url = plan.bus_url;
  request.bus_key = remote.bus_key;
  request.run_id = plan.run_id;
  request.data_dir = plan.data_dir.empty() ? "" : fs::absolute(plan.data_dir).string();
  request.dir = slurm_dir.string();
  auto workers = std::make_unique<remote_ns::SlurmWorkers>(request);
  std::printf("Slurm job array %s: %d worker(s), logs in %s\n", workers->job_id().c_str(), o.slurm_workers,
              slurm_dir.c_str());
  return workers;
}

}  // namespace

int run_run(const RunOptions& options) {
  // A suite given as --tasks is run as the suite it is: exactly its tasks, named in the provenance.
  RunOptions o = options;
  if (!o.tasks.empty() && tasks::is_suite_file(o.tasks)) {
    o.suite = o.tasks;
    o.tasks.clear();
  }
  if (o.out.empty()) throw Error("--out <run dir> is required");
  if (o.given.count("--slurm")) {
    if (o.slurm_workers < 1) throw Error("--slurm-workers must be at least 1, not " + std::to_string(o.slurm_workers));
    if (o.worker_capacity < 1) throw Error("--worker-capacity must be at least 1, not " + std::to_string(o.worker_capacity));
  } else if (o.given.count("--slurm-workers") || o.given.count("--worker-capacity") || o.given.count("--hub-port") ||
             o.given.count("--hub-host")) {
    throw Error("--slurm-workers, --worker-capacity, --hub-port and --hub-host go with --slurm");
  }
  const fs::path dir = fs::absolute(o.out).lexically_normal();
  if (fs::exists(dir) && !fs::is_directory(dir)) throw Error("--out " + dir.string() + " is a file, not a run folder");
  // Before anything else, a resume included: no name the run writes is a planted link.
  orchestrator::check_run_folder(dir);
  RunPlan plan;
  const bool resuming = fs::exists(dir / "plan.json");
  // A suite is checked whole (format, digest, every task) before anything else.
  std::optional<tasks::Suite> suite;
  if (!o.suite.empty()) suite = tasks::read_suite(o.suite);
  if (resuming) {
    plan = orchestrator::load_plan(dir);
    check_resume(plan, o, dir, suite ? &*suite : nullptr);
    plan.allow_data_mismatch = o.allow_data_mismatch;  // a permission of this invocation
  } else {
    plan = plan_from_options(o, dir, suite ? &*suite : nullptr);
  }
  // Until the folder holds its copy, a new suite run reads the suite given.
  const std::string task_source = !resuming && suite ? o.suite : plan.tasks_db;
  // Everything is checked before anything is written: a typo must not spoil the folder.
  check_agents(plan.agents, o.vlm, plan.remote, o.estimate);
  // A new suite run takes its tasks and fingerprints from the suite read above: each read of the
  // file parses and hashes it whole (0.2 s for the standard suite).
  const bool from_suite = !resuming && suite;
  const auto tasks = by_id(from_suite ? suite->tasks : tasks::read_tasks(task_source));
  if (!resuming) plan = orchestrator::make_plan(std::move(plan), tasks);
  const auto fingerprints =
      fingerprints_of(plan, from_suite ? suite->dataset : tasks::read_dataset_fingerprints(task_source), tasks);
  if (!plan.remote) check_dataset(plan, task_source, fingerprints);
  // Loaded once for the goals and the estimate, and let go before the run's processes load their own.
  std::optional<graph::SceneCache> scenes(std::in_place, plan.profile, plan.platform_rules);
  check_goals(plan, task_source, tasks, *scenes);
  if (o.estimate) return orchestrator::print_estimate(plan, tasks, o.vlm, dir, &*scenes);
  if (!resuming) {
    const bool model_agent = std::any_of(plan.agents.begin(), plan.agents.end(),
                                         [](const std::string& a) { return vlm::is_model_spec(a); });
    plan.provenance = orchestrator::make_provenance(
        {o.command_line, task_source, fingerprints,
         model_agent ? o.vlm.resolve().provenance_json() : nlohmann::json(nullptr)});
    if (suite) {
      plan.provenance["suite"] = {{"id", suite->id()}, {"name", suite->name}, {"digest", suite->digest},
                                  {"file", fs::absolute(o.suite).lexically_normal().string()}};
    }
    plan.provenance["draw"] = draw_record(plan, tasks, suite.has_value());
  }
  // One writer per folder, from here to the end of the run (run_lock.h).
  const bool playing = plan.agents.size() == 1 && plan.agents.front() == agents::kHumanAgent;
  const orchestrator::RunLock lock(dir, playing ? "mtg play" : "mtg run");
  SlurmRun slurm;
  const std::string planned_bus = plan.bus_url;
  if (o.given.count("--slurm") && o.url.empty()) slurm.hub = start_run_hub(o, plan, dir);
  if (resuming) std::printf("resuming %s (run %s)\n", dir.c_str(), plan.run_id.c_str());
  if (!resuming || plan.bus_url != planned_bus) {
    fs::create_directories(dir);
    if (!resuming && suite) write_file_bytes_atomically(plan.tasks_db, read_file_bytes(o.suite));
    orchestrator::save_plan(plan, dir);
  }
  orchestrator::write_bus_file(dir, plan.bus_url);
  // Each invocation on the folder leaves a start and an end line (provenance.h).
  const std::string started = orchestrator::utc_now();
  orchestrator::append_session(dir, {{"event", "start"}, {"at", started}, {"host", host_name()},
                                     {"mtg_version", mtg_version()}, {"git_revision", mtg_git_revision()},
                                     {"command", o.command_line}, {"resumed", resuming}});
  orchestrator::EngineOptions engine;
  engine.dataset_json = scene::to_json(fingerprints).dump();
  engine.progress = !o.no_progress;
  engine.recorder = o.recorder;
  engine.renderers = o.renderers;
  engine.vlm_args = plan.remote ? run_wide(o.vlm).to_args() : o.vlm.to_args();
  engine.remote = o.remote_options;
  engine.remote.recordings = orchestrator::remote::parse_recordings_place(plan.recordings);
  engine.play_host = o.play_host;
  engine.hold_after_last = playing;
  engine.play_port = o.play_port;
  if (const char* socket = std::getenv(orchestrator::kPlaySocketEnv); socket != nullptr && orchestrator::inside_run_namespace()) {
    engine.play_socket = socket;
  }
  engine.budget = orchestrator::announce_estimate(o.max_cost_usd, plan, tasks, o.vlm, dir, &*scenes);
  scenes.reset();
  if (o.given.count("--slurm")) slurm.workers = submit_slurm_workers(o, plan, dir, engine.remote);
  const auto summary = orchestrator::run_plan(plan, dir, tasks, engine);
  slurm.workers.reset();  // cancel what is left of the array
  slurm.hub.reset();
  const nlohmann::json report = orchestrator::write_reports(dir);
  orchestrator::append_session(
      dir, {{"event", "end"}, {"at", orchestrator::utc_now()}, {"started", started}, {"host", host_name()},
            {"episodes_done", summary.completed}, {"given_up", summary.errors},
            {"ended", summary.interrupted                    ? "interrupted"
                      : !summary.stopped_agents.empty()       ? "agent stopped"
                      : !summary.budget_stop.empty()          ? "budget"
                                                              : "finished"}});
  print_summary(summary, dir, report, plan.remote);
  if (const std::string line = draw_line(plan.provenance); !line.empty()) std::printf("  %s\n", line.c_str());
  if (summary.interrupted) {
    std::printf("interrupted: run the same command again to resume\n");
    return 130;
  }
  if (!summary.stopped_agents.empty()) {
    for (const auto& [agent, why] : summary.stopped_agents) std::fprintf(stderr, "agent %s stopped: %s\n", agent.c_str(), why.c_str());
    std::fprintf(stderr, "%lld episode(s) not run; fix the cause and run the same command again to resume\n",
                 static_cast<long long>(summary.not_run));
    return 1;
  }
  if (!summary.budget_stop.empty()) {
    std::fprintf(stderr, "%s\n", summary.budget_stop.c_str());
    return 3;
  }
  if (summary.errors > 0) {
    // Not a success: a task whose goal does not resolve, a service that cannot start, a lost
    // host gave them up; the run's scores leave them out. A resume runs them again.
    std::fprintf(stderr,
                 "%lld episode(s) given up by the infrastructure, outside SR and IP (why: `mtg report %s`, "
                 "%s/logs); fix the cause and run the same command again to run them\n",
                 static_cast<long long>(summary.errors), dir.c_str(), dir.c_str());
    return 1;
  }
  return 0;
}

namespace {

// A run's report from its results and its people's marks (exclusions leave the figures).
nlohmann::json report_of(const fs::path& dir) {
  const auto marks = orchestrator::current_marks(orchestrator::read_marks(dir));
  return orchestrator::make_report(orchestrator::read_results(dir / "results.sqlite"), dir.filename().string(), &marks);
}

// The report of a run whose folder may be read-only (someone else's, a shared archive): what
// cannot be written is said in one line, and the report is printed all the same.
// A read-only run folder (someone else's run) still gets its report printed, and written to
// --html when one is named: that file is what the user asked for, so failing to write it is an
// error, not a note.
nlohmann::json write_reports_if_possible(const fs::path& dir, const std::string& html) {
  try {
    return orchestrator::write_reports(dir, html);
  } catch (const std::exception& e) {
    const nlohmann::json report = report_of(dir);
    if (html.empty()) {
      std::fprintf(stderr, "mtg report: the report files cannot be written (%s); printing it only\n", e.what());
      return report;
    }
    write_file_atomically(html, [&](std::ostream& out) { out << orchestrator::report_html(report); });
    std::fprintf(stderr, "mtg report: wrote only %s: %s\n", html.c_str(), e.what());
    return report;
  }
}

}  // namespace

int run_report(const ReportOptions& o) {
  const fs::path dir(o.run);
  if (!fs::exists(dir / "results.sqlite")) throw Error(dir.string() + ": not a run folder (no results.sqlite)");
  if (!o.json) orchestrator::check_run_folder(dir);  // it writes report.*, and card.* with --card
  // --json only reads; otherwise the files are written where the folder allows it.
  const nlohmann::json report =
      o.json ? report_of(dir) : write_reports_if_possible(dir, o.html);
  if (o.card) {
    orchestrator::write_card(dir);
    if (!o.json) std::printf("card: %s (+ card.json)\n", (dir / "card.md").c_str());
  }
  if (o.json) {
    std::cout << report.dump() << '\n';
    return 0;
  }
  std::printf("%s: %lld episodes scored, SR %s %%, IP %s (95 %% intervals)\n", dir.c_str(),
              static_cast<long long>(report["scored"].get<std::int64_t>()),
              orchestrator::with_interval(report, "sr").c_str(), orchestrator::with_interval(report, "ip").c_str());
  if (const auto given_up = report["errors"].get<std::int64_t>(); given_up > 0) {
    std::printf("  %lld episode(s) given up by the infrastructure, outside SR and IP: the same `mtg run` "
                "again on this folder runs them again\n",
                static_cast<long long>(given_up));
  }
  if (report.contains("excluded") && !report["excluded"].empty()) {
    std::printf("  %zu episode(s) excluded by a person (marks.sqlite), outside every figure below\n",
                report["excluded"].size());
  }
  // Table 3 of the paper, one line per agent and level, then the paper's average and all levels.
  const std::string avg = orchestrator::paper_average_label(report);
  // Padded by characters, not bytes: "Avg (L1–3)" holds a three-byte dash.
  auto padded = [](const std::string& s, std::size_t width) {
    const auto chars = static_cast<std::size_t>(std::count_if(s.begin(), s.end(), [](char c) { return (c & 0xC0) != 0x80; }));
    return s + std::string(width > chars ? width - chars : 1, ' ');  // a long name still gets its space
  };
  std::printf("  %s%s%8s  %s%s\n", padded("agent", 15).c_str(), padded("levels", 12).c_str(), "episodes",
              padded("SR % [95 % CI]", 23).c_str(), "IP [95 % CI]");
  auto line = [&padded](const std::string& agent, const std::string& levels, const nlohmann::json& f) {
    std::printf("  %s%s%8lld  %s%s\n", padded(agent, 15).c_str(), padded(levels, 12).c_str(),
                static_cast<long long>(f.value("episodes", std::int64_t{0})),
                padded(orchestrator::with_interval(f, "sr"), 23).c_str(), orchestrator::with_interval(f, "ip").c_str());
  };
  for (const auto& [agent, a] : report["by_agent"].items()) {
    for (const auto& [level, al] : a["by_level"].items()) line(agent, "L" + level, al);
    if (!a["paper_avg"].is_null()) {  // over this agent's own levels (a run may lack one of them)
      nlohmann::json f = a["paper_avg"];
      std::int64_t n = 0;
      for (const auto& l : f["levels"]) n += a["by_level"][l.get<std::string>()]["episodes"].get<std::int64_t>();
      f["episodes"] = n;
      line(agent, orchestrator::average_label(f["levels"]), f);
    }
    line(agent, "all", a);
  }
  for (const auto& [agent, a] : report["by_agent"].items()) {
    if (a.contains("repeats")) std::printf("  repeats of %s\n", orchestrator::repeats_text(agent, a["repeats"]).c_str());
  }
  if (fs::exists(dir / "plan.json")) {
    if (const std::string drawn = draw_line(orchestrator::load_plan(dir).provenance); !drawn.empty()) {
      std::printf("  %s\n", drawn.c_str());
    }
  }
  if (!report["causes"].empty()) {
    std::printf("  failure causes:");
    for (const auto& [cause, n] : report["causes"].items()) {
      std::printf(" %s %lld", cause.c_str(), static_cast<long long>(n.get<std::int64_t>()));
    }
    std::printf("\n");
  }
  if (::access(dir.c_str(), W_OK) == 0) {
    std::printf("  wrote %s, report.png, report.json\n", (o.html.empty() ? (dir / "report.html").string() : o.html).c_str());
  } else if (!o.html.empty()) {
    std::printf("  wrote %s\n", o.html.c_str());
  }
  return 0;
}

int run_compare(const CompareOptions& o) {
  auto load = [](const std::string& run) {
    fs::path named = fs::absolute(run).lexically_normal();
    if (!named.has_filename()) named = named.parent_path();  // "runs/a/"
    return orchestrator::load_run_rows(run, named.filename().string());
  };
  const orchestrator::RunRows a = load(o.run_a);
  std::optional<orchestrator::RunRows> b;
  if (!o.run_b.empty()) b = load(o.run_b);
  const nlohmann::json comparison = orchestrator::compare_runs(a, b ? &*b : nullptr, o.agent, o.baseline);
  if (o.json) {
    std::cout << comparison.dump() << '\n';
  } else {
    std::cout << orchestrator::compare_text(comparison);
  }
  return 0;
}

int run_replay(const ReplayOptions& o) {
  const fs::path src = fs::absolute(o.run).lexically_normal();
  RunPlan plan = orchestrator::load_plan(src);
  const fs::path dir = o.out.empty() ? src / "replay" : fs::absolute(o.out).lexically_normal();
  orchestrator::check_run_folder(src);
  if (fs::exists(dir / "results.sqlite")) fs::remove_all(dir);  // a replay always starts afresh (links removed, not followed)
  orchestrator::check_run_folder(dir);
  fs::create_directories(dir);
  const std::string spec = "replay:" + src.string();
  plan.run_id = plan.run_id + "-replay";
  plan.agents = {spec};
  for (auto& e : plan.episodes) e.agent = spec;
  plan.parallel = std::max(1, o.parallel);
  // A multi-host run replays on this machine: its workers and shared bus are not needed to
  // re-drive services from its (merged) recording.
  plan.remote = false;
  plan.bus_url = o.url.empty() ? bus::default_url() : bus::normalize_url(o.url);
  // What made the replay, beside what made the run it replays (kept: its task set and settings).
  if (plan.provenance.is_object()) {
    plan.provenance["replay"] = {{"mtg_version", mtg_version()}, {"git_revision", mtg_git_revision()},
                                 {"host", host_name()}, {"at", orchestrator::utc_now()}, {"of", src.string()}};
  }
  orchestrator::save_plan(plan, dir);
  const auto tasks = load_tasks(plan.tasks_db);
  const auto summary = orchestrator::run_plan(plan, dir, tasks);
  orchestrator::write_reports(dir);
  const auto original = orchestrator::read_results(src / "results.sqlite");
  const auto replayed = orchestrator::read_results(dir / "results.sqlite");
  std::map<bus::EpisodeId, std::string> again;
  for (const auto& r : replayed) again[r.episode_id] = orchestrator::verdict_fingerprint(r);
  std::int64_t same = 0, compared = 0;
  for (const auto& r : original) {
    if (r.status != "scored") continue;
    ++compared;
    const auto it = again.find(r.episode_id);
    if (it != again.end() && it->second == orchestrator::verdict_fingerprint(r)) {
      ++same;
    } else {
      std::printf("  differs: episode %lld (%s)\n", static_cast<long long>(r.episode_id.value()), r.task_id.c_str());
    }
  }
  std::printf("replay of %s: %lld / %lld judge results identical (%.1f s); replay in %s\n", src.c_str(),
              static_cast<long long>(same), static_cast<long long>(compared), summary.seconds, dir.c_str());
  return same == compared ? 0 : 1;
}

int run_rejudge(const std::string& run) {
  const fs::path dir = fs::absolute(run).lexically_normal();
  orchestrator::check_run_folder(dir);
  const auto report = orchestrator::rejudge_run(dir);
  const fs::path out = dir / "rejudge.sqlite";
  fs::remove(out);
  {
    orchestrator::ResultsDb db(out);
    for (const auto& row : report.rows) db.insert(row);
  }
  for (const auto& d : report.damage) std::fprintf(stderr, "mtg rejudge: %s\n", d.c_str());
  for (const auto& u : report.unjudged) std::fprintf(stderr, "mtg rejudge: %s: not judged again\n", u.c_str());
  for (const auto& d : report.differences) std::printf("  %s\n", d.c_str());
  std::printf("rejudged %zu episodes of %s from the recording: %lld identical, %zu differ%s; wrote %s\n",
              report.rows.size(), dir.c_str(), static_cast<long long>(report.identical), report.differences.size(),
              report.unjudged.empty() ? "" : (", " + std::to_string(report.unjudged.size()) + " not judged (above)").c_str(),
              out.c_str());
  // A recording that cannot be read whole cannot say the verdicts hold.
  return report.unjudged.empty() ? 0 : 1;
}

}  // namespace mtg::cli
