#include "orchestrator/cli/suite_commands.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

#include "core/scene/dataset.h"
#include "core/scene/dataset_fingerprint.h"
#include "core/stats/power.h"
#include "core/tasks/generator.h"
#include "core/tasks/suite.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "orchestrator/run/goal_check.h"

namespace mtg::cli {

namespace fs = std::filesystem;

namespace {

std::string format(const char* pattern, double a, double b = 0, double c = 0, double d = 0, double e = 0) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b, c, d, e);
  return text;
}

// Tasks per (scene, level) as a table: "apt_0  L1 100  L2 100 ...".
void print_counts(const tasks::Suite& s) {
  std::map<std::string, std::map<int, int>> counts;
  for (const auto& t : s.tasks) ++counts[t.scene][t.level];
  for (const auto& [scene, levels] : counts) {
    std::printf("  %-12s", scene.c_str());
    for (const auto& [level, n] : levels) std::printf("  L%d %4d", level, n);
    std::printf("\n");
  }
}

void print_spread(const nlohmann::json& spread) {
  for (const auto& [level, sp] : spread.items()) {
    std::printf("  L%s: biggest %s %s, %lld of %lld tasks (%.1f %%) among %lld %ss\n", level.c_str(),
                sp["stratum"].get<std::string>().c_str(), sp["biggest"].get<std::string>().c_str(),
                static_cast<long long>(sp["biggest_tasks"].get<std::int64_t>()),
                static_cast<long long>(sp["tasks"].get<std::int64_t>()), 100.0 * sp["biggest_share"].get<double>(),
                static_cast<long long>(sp["strata"].get<std::int64_t>()), sp["stratum"].get<std::string>().c_str());
  }
}

}  // namespace

SuiteSizing size_suite(double mde_points, double power, double discordance, double alpha, int scenes) {
  stats::McNemarSizeInputs in;
  in.difference = mde_points / 100.0;
  in.discordance = discordance;
  in.alpha = alpha;
  in.power = power;
  const stats::McNemarSize n = stats::mcnemar_pairs_needed(in);
  SuiteSizing s;
  s.per_level = n.pairs;
  s.per_scene = static_cast<int>((n.pairs + scenes - 1) / scenes);
  s.explanation.push_back(format("paired comparison of two agents, exact McNemar test on success, two-sided alpha %g, power %g",
                                 alpha, power));
  s.explanation.push_back(format("detect an SR difference of delta = %g points with discordance psi = %g (share of tasks "
                                 "where exactly one agent succeeds)",
                                 mde_points, discordance));
  s.explanation.push_back(format("n = (z_{1-a/2} sqrt(psi) + z_{1-b} sqrt(psi - delta^2))^2 / delta^2 "
                                 "= (%.4f * %.4f + %.4f * %.4f)^2 / %.4f",
                                 n.z_alpha, std::sqrt(discordance), n.z_beta, std::sqrt(discordance - in.difference * in.difference),
                                 in.difference * in.difference) +
                          format(" = %.2f -> %.0f tasks per level (Connor 1987)", n.exact, static_cast<double>(n.pairs)));
  s.explanation.push_back(format("over %.0f scene(s): %.0f tasks per scene and level", scenes, s.per_scene));
  return s;
}

int run_suite_make(const SuiteMakeOptions& o) {
  if (o.tasks.empty()) throw Error("--tasks <tasks.sqlite> is required");
  if (o.name.empty()) throw Error("--name is required (e.g. standard-replicacad)");
  if (o.out.empty()) throw Error("--out <suite file> is required");
  const bool sized = o.given.count("--mde") != 0;
  if (sized == (o.given.count("--per-level") != 0)) throw Error("give either --per-level N or --mde POINTS");
  if (!sized && (o.given.count("--power") || o.given.count("--discordance") || o.given.count("--alpha"))) {
    throw Error("--power, --discordance and --alpha go with --mde");
  }
  if (!sized && o.per_level < 1) throw Error("--per-level must be at least 1, not " + std::to_string(o.per_level));
  if (tasks::is_suite_file(o.tasks)) throw Error(o.tasks + " is a suite; draw a suite from a task set (mtg tasks --out)");
  tasks::SuiteDraw draw;
  draw.seed = o.seed;
  draw.kind = tasks::draw_kind_from_string(o.draw);
  draw.levels = tasks::parse_levels(o.levels);
  draw.scenes = {o.scenes.begin(), o.scenes.end()};
  const auto all = tasks::read_tasks(o.tasks, draw.levels);
  const auto dataset = tasks::read_dataset_fingerprints(o.tasks);
  std::set<std::string> scenes = draw.scenes;
  if (scenes.empty()) {
    for (const auto& t : all) scenes.insert(t.scene);
  }
  if (sized) {
    const SuiteSizing size = size_suite(o.mde, o.power, o.discordance, o.alpha, std::max<int>(1, static_cast<int>(scenes.size())));
    for (const auto& line : size.explanation) std::printf("sizing: %s\n", line.c_str());
    draw.per_level = size.per_scene;
    draw.sizing = {{"mde_points", o.mde}, {"power", o.power}, {"discordance", o.discordance}, {"alpha", o.alpha},
                   {"tasks_per_level", size.per_level}, {"scenes", scenes.size()}, {"method", "McNemar, Connor 1987"}};
  } else {
    draw.per_level = o.per_level;
  }
  nlohmann::json generator = {
      {"task_format", tasks::read_task_set_meta(o.tasks, "generator_version").value_or("unknown")},
      {"config_hash", tasks::read_task_set_meta(o.tasks, "config_hash").value_or("unknown")},
      {"config", tasks::read_generator_config(o.tasks)},
      {"seed", tasks::read_task_set_meta(o.tasks, "seed").value_or("unknown")}};
  tasks::Suite suite = tasks::draw_suite(o.name, all, draw, std::move(generator), dataset);
  // Levels asked for that the set lacks in a scene leave that (scene, level) short: say so.
  std::map<std::pair<std::string, int>, int> got;
  for (const auto& t : suite.tasks) ++got[{t.scene, t.level}];
  for (const auto& scene : suite.draw.scenes) {
    for (const int level : suite.draw.levels) {
      const int n = got[{scene, level}];
      if (n < suite.draw.per_level) {
        std::fprintf(stderr, "mtg suite make: %s L%d has %d task(s), fewer than %d: all are in the suite\n", scene.c_str(), level,
                     n, suite.draw.per_level);
      }
    }
  }
  tasks::write_suite(o.out, suite);
  std::printf("suite %s: %zu tasks (%s draw, seed %llu) -> %s\n", suite.id().c_str(), suite.tasks.size(),
              tasks::to_string(suite.draw.kind), static_cast<unsigned long long>(suite.draw.seed), o.out.c_str());
  print_counts(suite);
  std::printf("spread (per level, the biggest stratum's share of its scene's tasks, in the most lopsided scene):\n");
  print_spread(tasks::suite_spread(suite));
  std::printf("digest %s\n", suite.digest.c_str());
  return 0;
}

int run_suite_info(const SuiteInfoOptions& o) {
  const tasks::Suite s = tasks::read_suite(o.file);
  nlohmann::json content = tasks::suite_content(s);
  if (o.json) {
    content.erase("tasks");
    content["id"] = s.id();
    content["digest"] = s.digest;
    content["made_with"] = s.made_with;
    content["tasks"] = s.tasks.size();
    content.erase("dataset");
    content["dataset_digests"] = nlohmann::json::object();
    for (const auto& [scene, f] : s.dataset) content["dataset_digests"][scene] = f.digest();
    std::cout << content.dump() << '\n';
    return 0;
  }
  std::printf("suite %s: %zu tasks, digest %s\n", s.id().c_str(), s.tasks.size(), s.digest.c_str());
  std::printf("  drawn: %s, %d per scene and level, seed %llu", tasks::to_string(s.draw.kind), s.draw.per_level,
              static_cast<unsigned long long>(s.draw.seed));
  if (!s.draw.sizing.is_null()) {
    std::printf(" (sized for %g SR points at power %g, discordance %g)", s.draw.sizing.value("mde_points", 0.0),
                s.draw.sizing.value("power", 0.0), s.draw.sizing.value("discordance", 0.0));
  }
  std::printf("\n  generator: %s, config %s\n", s.generator.value("task_format", std::string("?")).c_str(),
              s.generator.value("config_hash", std::string("?")).c_str());
  std::printf("  made with: mtg %s (%s)\n", s.made_with.value("mtg_version", std::string("?")).c_str(),
              s.made_with.value("git_revision", std::string("?")).c_str());
  for (const auto& [scene, f] : s.dataset) std::printf("  dataset %-10s %s (%zu files)\n", scene.c_str(), f.digest().c_str(), f.files.size());
  print_counts(s);
  print_spread(content["spread"]);
  std::printf("  license: %s\n", s.license.c_str());
  return 0;
}

int run_suite_verify(const SuiteVerifyOptions& o) {
  const tasks::Suite s = tasks::read_suite(o.file);  // format, digest, id, every task
  const fs::path root = scene::resolve_data_root(o.data_dir);
  const std::string diff = scene::first_difference(s.dataset, root);
  if (!diff.empty()) {
    throw Error(o.file + ": the dataset at " + root.string() + " is not the one suite " + s.id() + " was made from (" + diff + ")");
  }
  std::vector<const tasks::Task*> list;
  for (const auto& t : s.tasks) list.push_back(&t);
  orchestrator::check_goals(list, o.profile, tasks::platform_rules_of_format(s.generator.value("task_format", std::string())),
                            o.data_dir, o.file, orchestrator::MissingScene::kFail);
  std::printf("%s: suite %s verified: %zu tasks, the digest matches, the dataset at %s is the suite's, every goal "
              "resolves\n",
              o.file.c_str(), s.id().c_str(), s.tasks.size(), root.c_str());
  return 0;
}

}  // namespace mtg::cli
