#include "core/tasks/job.h"

#include <algorithm>
#include <filesystem>
#include <future>
#include <mutex>
#include <optional>
#include <set>
#include <utility>

#include "core/graph/build.h"
#include "core/render/visibility.h"
#include "core/scene/scene_loader.h"
#include "core/tasks/generator.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "core/util/parallel.h"
#include "core/util/stopwatch.h"

namespace mtg::tasks {

GenerationReport run_generation(const GenerationJob& job, const SceneDone& on_scene) {
  if (job.scenes.empty()) throw Error("no scene given");
  if (job.out.empty()) throw Error("no output database given");
  const Stopwatch total;
  const auto dataset = scene::index_dataset(scene::resolve_data_root(job.data_dir));
  for (const std::string& name : job.scenes) dataset.scene_file(name);  // a typo fails now, not after other scenes
  graph::GraphOptions graph_options;
  graph::apply_profile(graph_options, job.profile);
  graph_options.platform_rules = platform_rules_of_format(kGeneratorVersion);  // the graphs the tasks are planned on

  // Scenes run side by side (each also spreads its own levels over the threads). Each scene's
  // thread makes its tasks into chunks as they come, without the lock; the first scene not yet
  // finished stores them at once, a later scene keeps them (compressed) until every scene before
  // it is in. A finished scene's row is reported then. So the files and the report are the same
  // for any number of threads, and no scene's tasks are held as tasks: a later scene that
  // finishes first waits whole, but as chunks. Live voters (model calls) are not made for
  // concurrent use: with them, one scene at a time.
  struct SceneOutput {
    SceneReport report;
    GenerationResult result;
    std::vector<Task> rest;           // fewer than a chunk's worth, not yet made into one
    std::vector<TaskChunk> waiting;   // made while an earlier scene was still being written
    bool done = false;
  };
  std::vector<SceneOutput> outputs(job.scenes.size());
  scene::FileHashes file_hashes;  // the scenes share most files: each is read and hashed once
  TaskDbWriter writer(job.out, job.options, job.jsonl, job.jobs);
  GenerationReport report;
  std::vector<Vote> votes;
  std::mutex progress_mutex;  // on_progress is called one at a time
  const auto told = [&](std::size_t i, SceneProgress::Phase phase, std::int64_t tasks) {
    if (!job.on_progress) return;
    const std::lock_guard<std::mutex> lock(progress_mutex);
    job.on_progress({i, phase, tasks});
  };
  std::mutex writing;    // the writer's store(), `head` and every scene's `waiting`
  std::size_t head = 0;  // the scene whose chunks go into the database now
  // Called on scene i's thread only, in its task order.
  const auto take = [&](std::size_t i, std::vector<Task> batch, bool last) {
    SceneOutput& out = outputs[i];
    for (const Task& t : batch) out.report.levels[static_cast<std::size_t>(t.level - 1)] += 1;
    if (!batch.empty()) {
      told(i, SceneProgress::Phase::kTasks,
           out.report.levels[0] + out.report.levels[1] + out.report.levels[2] + out.report.levels[3]);
    }
    out.rest.insert(out.rest.end(), std::make_move_iterator(batch.begin()), std::make_move_iterator(batch.end()));
    std::vector<TaskChunk> chunks = writer.make_chunks(out.rest, last);
    const std::lock_guard<std::mutex> lock(writing);
    if (i == head) {
      writer.store(std::move(chunks));
    } else {
      out.waiting.insert(out.waiting.end(), std::make_move_iterator(chunks.begin()),
                         std::make_move_iterator(chunks.end()));
    }
  };
  // A scene runs for every two threads (one scene keeps about 1.5 cores busy with its levels
  // and its Level 4 alongside): on two cores the scenes take turns, which costs no time and holds
  // one scene's sight data at a time (three apartments: 220 -> 140 MB peak, wall time within 1.3 %;
  // docs/benchmarks.md "One scene per two threads"). Each scene's levels get twice its share: when
  // scenes finish unevenly the last ones still use every core. At most twice the threads asked
  // for, plus one per running scene for its Level 4 (generate_tasks), never jobs x jobs.
  const int scene_jobs = job.voters.empty() ? std::clamp<int>(job.jobs / 2, 1, static_cast<int>(job.scenes.size())) : 1;
  const int level_jobs = std::min(job.jobs, std::max(1, 2 * job.jobs / std::max(1, scene_jobs)));
  parallel_for(job.scenes.size(), scene_jobs, [&](std::size_t i) {
    const Stopwatch watch;
    const std::string& name = job.scenes[i];
    graph::SceneGraph g;
    render::SceneGeometry geometry;  // the triangles the agent's views draw (visibility rules)
    std::set<std::filesystem::path> source_files;
    std::future<scene::DatasetFingerprint> fingerprint;
    told(i, SceneProgress::Phase::kLoading, 0);
    {  // the meshes (scene and cache) are not needed for tasks beyond their triangles: gone before generation
      scene::MeshCache cache(scene::MeshLoadOptions{.keep_textures = false});
      // Meshes on several threads only when this scene has the machine to itself: scenes side by
      // side keep every core busy already, and their imports at once raised the peak by 15 MiB.
      scene::Scene loaded = scene::load_scene(dataset, name, cache, {.jobs = scene_jobs == 1 ? level_jobs : 1});
      source_files = std::move(loaded.source_files);
      // Reading and hashing the scene's files takes a core for a fifth of a second, one at a
      // time: alongside the graph and the tasks, not after them.
      fingerprint = std::async(std::launch::async, [&dataset, &source_files, &file_hashes] {
        return scene::fingerprint_files(dataset.root, source_files, &file_hashes);
      });
      told(i, SceneProgress::Phase::kGraph, 0);
      g = graph::build_scene_graph(loaded, graph_options);
      if (job.options.visibility) geometry = render::SceneGeometry(loaded, g);
    }
    SceneOutput& out = outputs[i];
    told(i, SceneProgress::Phase::kTasks, 0);
    std::optional<render::VisibilityOracle> seeing;
    if (job.options.visibility) seeing.emplace(g, geometry, *job.options.visibility);
    out.result = generate_tasks(g, job.options, job.votes, job.voters, level_jobs,
                                [&take, i](std::vector<Task> batch) { take(i, std::move(batch), false); },
                                seeing ? &*seeing : nullptr);
    take(i, {}, true);  // the short chunk at the end
    out.result.set.dataset = fingerprint.get();
    SceneReport& sr = out.report;
    sr.scene = name;
    for (const std::int64_t n : sr.levels) sr.total += n;
    sr.seconds = watch.elapsed_ms() / 1000.0;
    told(i, SceneProgress::Phase::kDone, sr.total);
    const std::lock_guard<std::mutex> lock(writing);
    out.done = true;
    while (head < outputs.size() && outputs[head].done) {
      SceneOutput& ready = outputs[head];
      writer.end_scene(ready.result.set);
      const SceneReport& done = ready.report;
      for (std::size_t l = 0; l < 4; ++l) report.levels[l] += done.levels[l];
      report.total += done.total;
      for (const auto& w : ready.result.set.warnings) report.warnings.push_back(done.scene + ": " + w);
      report.scenes.push_back(done);
      votes.insert(votes.end(), ready.result.votes.begin(), ready.result.votes.end());
      ready.result = {};
      if (on_scene) on_scene(done);
      if (++head < outputs.size()) writer.store(std::exchange(outputs[head].waiting, {}));
    }
  });
  writer.finish(votes);
  report.seconds = total.elapsed_ms() / 1000.0;
  return report;
}

void apply_overrides(GenerationJob& job, const nlohmann::json& o) {
  if (o.is_null()) return;
  if (!o.is_object()) throw Error("generator config: expected a JSON object");
  for (const auto& [key, value] : o.items()) {
    try {
      if (key == "levels") job.options.levels = parse_levels(value.get<std::string>());
      else if (key == "seed") job.options.seed = json_integer<std::uint64_t>(value, "generator config: seed");
      else if (key == "ambiguity") job.options.ambiguity = ambiguity_from_string(value.get<std::string>());
      else if (key == "l3_count") job.options.level3_count = json_integer<int>(value, "generator config: l3_count");
      else if (key == "l3_chain") job.options.level3_chain = json_integer<int>(value, "generator config: l3_chain");
      else if (key == "l4_max_moves") job.options.level4_max_moves = json_integer<int>(value, "generator config: l4_max_moves");
      else if (key == "l4_templates") job.options.level4_templates = value.get<std::string>();
      else if (key == "l4_max_share") {
        const double share = value.get<double>();
        if (!(share > 0.0 && share <= 1.0)) throw Error("generator config: l4_max_share must be above 0 and at most 1");
        job.options.level4_max_kind_share = share;
      }
      else if (key == "step_limit") job.options.rules.step_limit = json_integer<int>(value, "generator config: step_limit");
      else if (key == "profile") job.profile = value.get<std::string>();
      else throw Error("generator config: unknown key '" + key + "'");
    } catch (const nlohmann::json::exception&) {
      throw Error("generator config: bad value for '" + key + "'");
    }
  }
}

}  // namespace mtg::tasks
