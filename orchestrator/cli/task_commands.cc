#include "orchestrator/cli/task_commands.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <utility>

#include "agents/vlm/model_client.h"
#include "agents/vlm/model_setup.h"
#include "agents/vlm/voter.h"
#include "core/tasks/generator.h"
#include "core/tasks/job.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "core/util/parallel.h"
#include "core/util/stopwatch.h"

namespace mtg::cli {

int run_tasks(const TasksOptions& o) {
  if (o.scenes.empty()) throw Error("mtg tasks: --scene is required");
  if (o.out.empty()) throw Error("mtg tasks: --out is required");
  tasks::GenerationJob job;
  job.scenes = o.scenes;
  job.data_dir = o.data_dir;
  job.profile = o.profile;
  job.out = o.out;
  job.jsonl = o.jsonl;
  job.jobs = jobs_or_cores(o.jobs);
  job.options.levels = tasks::parse_levels(o.levels);
  job.options.seed = o.seed;
  job.options.ambiguity = tasks::ambiguity_from_string(o.ambiguity);
  if (o.visibility == "off") job.options.visibility.reset();
  else if (o.visibility != "on") throw Error("--visibility must be on or off, not '" + o.visibility + "'");
  job.options.level3_count = o.level3_count;
  job.options.level3_chain = o.level3_chain;
  job.options.level4_max_moves = o.level4_max_moves;
  if (!(o.level4_max_kind_share > 0.0 && o.level4_max_kind_share <= 1.0)) {
    throw Error("--l4-max-share must be above 0 and at most 1");
  }
  job.options.level4_max_kind_share = o.level4_max_kind_share;
  job.options.level4_templates = o.level4_templates;
  job.options.rules.step_limit = o.step_limit;
  if (!o.votes.empty()) job.votes = tasks::load_votes(o.votes);

  // Live voters: one model client each (cache, retries, a local rate gate), voting in parallel.
  struct Voter {
    vlm::ModelSetup setup;
    std::unique_ptr<vlm::LocalRateGate> gate;
    std::unique_ptr<vlm::ModelClient> client;
    vlm::VoteTally tally;
  };
  std::vector<std::unique_ptr<Voter>> voters;
  if (!o.voters.empty()) {
    if (!job.options.levels.count(4)) throw Error("mtg tasks: --voter votes on Level 4 tasks; add 4 to --levels");
    const vlm::VlmSettings settings = o.vlm.resolve();
    for (const std::string& spec : o.voters) {
      auto v = std::make_unique<Voter>();
      v->setup = vlm::ModelSetup::make(spec, settings);
      v->gate = std::make_unique<vlm::LocalRateGate>(v->setup.limits());
      v->client = std::make_unique<vlm::ModelClient>(v->setup.spec, v->setup.key, v->setup.settings, v->setup.prices,
                                                     v->setup.cache.get(), v->gate.get());
      Voter* raw = v.get();
      job.voters.push_back([raw](const std::vector<tasks::VoteRequest>& requests) {
        return vlm::cast_votes(*raw->client, raw->setup.prompts, requests, raw->setup.settings.workers, raw->tally);
      });
      voters.push_back(std::move(v));
    }
  }

  // On a terminal, one line that says where every scene stands, redrawn at most 5 times a second
  // (stderr, erased before each row and at the end; nothing of it in logs).
  std::vector<std::string> states(job.scenes.size(), "waiting");
  const Stopwatch started;
  double drawn_ms = -1e9;
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  auto draw = [&](bool force) {
    if (!tty || (!force && started.elapsed_ms() - drawn_ms < 200)) return;
    drawn_ms = started.elapsed_ms();
    std::string line;
    for (std::size_t i = 0; i < states.size(); ++i) line += (i ? " · " : "") + job.scenes[i] + " " + states[i];
    std::fprintf(stderr, "\r\033[K%s  %.0f s", line.c_str(), drawn_ms / 1000.0);
    std::fflush(stderr);
  };
  auto erase = [&] {
    if (tty) std::fprintf(stderr, "\r\033[K");
  };
  if (tty) {
    job.on_progress = [&](const tasks::SceneProgress& p) {
      using Phase = tasks::SceneProgress::Phase;
      switch (p.phase) {
        case Phase::kLoading: states[p.index] = "loading meshes"; break;
        case Phase::kGraph: states[p.index] = "scene graph"; break;
        case Phase::kTasks: states[p.index] = std::to_string(p.tasks) + " tasks"; break;
        case Phase::kDone: states[p.index] = "done"; break;
      }
      draw(p.phase != Phase::kTasks);
    };
  }
  // A row as each scene is done: a job over several apartments takes a while. The header comes
  // with the first row, so a job refused at once (a misspelt scene) prints only its error.
  bool header = false;
  tasks::GenerationReport report;
  try {
    report = tasks::run_generation(job, [&](const tasks::SceneReport& s) {
      erase();
      if (!std::exchange(header, true)) {
        std::printf("%-8s %8s %8s %8s %8s %9s %9s\n", "scene", "L1", "L2", "L3", "L4", "total", "time");
      }
      std::printf("%-8s %8ld %8ld %8ld %8ld %9ld %7.1f s\n", s.scene.c_str(), static_cast<long>(s.levels[0]),
                  static_cast<long>(s.levels[1]), static_cast<long>(s.levels[2]), static_cast<long>(s.levels[3]),
                  static_cast<long>(s.total), s.seconds);
      std::fflush(stdout);
      draw(true);
    });
  } catch (...) {
    erase();  // the error's line starts clean
    throw;
  }
  erase();
  for (const auto& w : report.warnings) log::warn(w);
  std::printf("wrote %s (%.1f s in all, peak RSS %.0f MiB)\n", o.out.c_str(), report.seconds, peak_rss_mib());
  if (!o.jsonl.empty()) std::printf("wrote %s\n", o.jsonl.c_str());
  for (const auto& v : voters) {
    std::printf("voter %s (prompts %s): %d asked, %d votes, %d unreadable, %d failed, %d from the cache, $%.4f\n",
                v->setup.spec.spec().c_str(), v->setup.prompts.version.c_str(), v->tally.asked, v->tally.cast,
                v->tally.unreadable, v->tally.failed, v->tally.cache_hits, v->tally.cost_usd);
  }
  return 0;
}

namespace {

std::string join_names(const nlohmann::json& names) {
  std::string out;
  for (const nlohmann::json& n : names) out += (out.empty() ? "" : ", ") + n.get<std::string>();
  return out;
}

}  // namespace

int run_task_stats(const TaskStatsOptions& o) {
  const nlohmann::json stats = tasks::task_db_stats(o.db);
  if (o.json) {
    std::cout << stats.dump() << '\n';
    return 0;
  }
  std::printf("%s: %ld tasks\n", o.db.c_str(), stats["total"].get<long>());
  for (const auto& [level, n] : stats["levels"].items()) std::printf("  level %s  %8ld\n", level.c_str(), n.get<long>());
  for (const auto& [type, n] : stats["types"].items()) std::printf("  %-28s %8ld\n", type.c_str(), n.get<long>());
  for (const auto& [scene, counts] : stats["scenes"].items()) {
    const long l1 = counts["1"].get<long>(), l2 = counts["2"].get<long>();
    std::printf("  %-8s L1 %ld  L2 %ld  L3 %ld  L4 %ld  (L1 share of L1+L2: %.1f %%)\n", scene.c_str(), l1, l2,
                counts["3"].get<long>(), counts["4"].get<long>(), l1 + l2 > 0 ? 100.0 * l1 / (l1 + l2) : 0.0);
  }
  // Level 4's catalogue: kinds present, tasks and phrasings used, the largest kind's share.
  const nlohmann::json catalogue = stats.value("outcome_kinds", nlohmann::json::object());
  for (const auto& [scene, kinds] : catalogue.items()) {
    long total = 0, largest = 0, templates = 0;
    for (const auto& [kind, c] : kinds.items()) {
      total += c["tasks"].get<long>();
      largest = std::max(largest, c["tasks"].get<long>());
      templates += c["templates"].get<long>();
    }
    std::printf("  %-8s Level 4: %zu kinds, %ld phrasings used, largest kind %.1f %% of %ld\n", scene.c_str(), kinds.size(),
                templates, total > 0 ? 100.0 * static_cast<double>(largest) / static_cast<double>(total) : 0.0, total);
    for (const auto& [kind, c] : kinds.items()) {
      std::printf("  %-8s   %-28s %6ld  (%ld phrasings)\n", scene.c_str(), kind.c_str(), c["tasks"].get<long>(),
                  c["templates"].get<long>());
    }
  }
  const nlohmann::json notes = stats.value("warnings", nlohmann::json::object());
  for (const auto& [scene, lines] : notes.items()) {
    for (const nlohmann::json& line : lines) std::printf("  %-8s note: %s\n", scene.c_str(), line.get<std::string>().c_str());
  }
  // Breadth beside the drops (docs/tasks.md, "Breadth").
  for (const auto& [scene, c] : stats["coverage"].items()) {
    const long pickable = c["pickable"].get<long>();
    auto pct = [&](long n) { return pickable > 0 ? 100.0 * static_cast<double>(n) / static_cast<double>(pickable) : 0.0; };
    std::printf("  %-8s coverage: %ld pickable items on navigable platforms; in Levels 1-2 %ld (%.0f %%), in any task "
                "%ld (%.0f %%); seen with look-alikes %ld, in Level 2 %ld; Level 2 from its top 3 source platforms "
                "%.0f %%; Levels 1-2: %ld source platforms, %ld nouns, %ld reference phrases\n",
                scene.c_str(), pickable, c["in_levels_1_2"].get<long>(), pct(c["in_levels_1_2"].get<long>()),
                c["in_any_task"].get<long>(), pct(c["in_any_task"].get<long>()), c["seen_with_lookalike"].get<long>(),
                c["seen_with_lookalike_in_level_2"].get<long>(), 100.0 * c["level_2_top3_share"].get<double>(),
                c["source_platforms_1_2"].get<long>(), c["nouns_1_2"].get<long>(), c["phrases_1_2"].get<long>());
    if (!c["not_in_levels_1_2"].empty()) {
      std::printf("  %-8s not in Levels 1-2: %s\n", scene.c_str(), join_names(c["not_in_levels_1_2"]).c_str());
    }
  }
  // Candidates the generator left out, and why (docs/tasks.md, "What is never generated").
  for (const auto& [scene, reasons] : stats["dropped"].items()) {
    for (const auto& [reason, levels] : reasons.items()) {
      std::printf("  %-8s dropped %-15s", scene.c_str(), reason.c_str());
      for (const auto& [level, n] : levels.items()) std::printf("  L%s %ld", level.c_str(), n.get<long>());
      std::printf("\n");
    }
  }
  return 0;
}

}  // namespace mtg::cli
