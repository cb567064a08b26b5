#pragma once
// A fixture for tests that run `mtg run` for real: the two-tables scene (three boxes and an empty
// table), its task set of Levels 1-3, and helpers to start runs, wait for and read their results.

#include <gtest/gtest.h>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/tasks/generator.h"
#include "core/tasks/task_db.h"
#include "orchestrator/run/results_db.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/process.h"
#include "tests/support/text_file.h"

namespace mtg::testing {

namespace fs = std::filesystem;
using orchestrator::EpisodeRow;

class RunFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    built_ = two_tables(fx_);
    tasks::TaskOptions options;
    options.level3_count = 40;
    options.levels = {1, 2, 3};
    const auto generated = tasks::generate_tasks(built_.scene, built_.graph, options);
    tasks_db_ = (fx_.root() / "tasks.sqlite").string();
    tasks::write_task_db(tasks_db_, {generated.set}, generated.votes, options);
  }

  std::vector<std::string> run_args(const std::string& out, const std::vector<std::string>& agents, int limit,
                                    int parallel) {
    std::vector<std::string> args = {bin("mtg"), "run", "--tasks", tasks_db_, "--levels", "1,2,3", "--limit",
                                     std::to_string(limit), "--parallel", std::to_string(parallel), "--out",
                                     (fx_.root() / out).string(), "--data", fx_.root().string(), "--profile", "none",
                                     "--episode-timeout", "5", "--no-progress"};
    for (const auto& a : agents) {
      args.push_back("--agent");
      args.push_back(a);
    }
    return args;
  }

  int mtg(const std::vector<std::string>& args, int timeout_ms = 120000) {
    ChildProcess p(args, log());
    return p.wait(timeout_ms);
  }

  std::string log() const { return (fx_.root() / "mtg.log").string(); }
  std::string log_text() const { return read_text(log()); }
  // The log's last line that is not empty: what a refused command said.
  std::string last_line() const {
    std::istringstream in(log_text());
    std::string line, last;
    while (std::getline(in, line)) {
      if (!line.empty()) last = line;
    }
    return last;
  }

  std::vector<EpisodeRow> results(const std::string& out) {
    return orchestrator::read_results(fx_.root() / out / "results.sqlite");
  }

  std::size_t planned(const std::string& out) {
    std::ifstream in(fx_.root() / out / "plan.json");
    return nlohmann::json::parse(in)["episodes"].size();
  }

  // Waits until the run has at least `n` results (polling the database), up to `timeout_ms`.
  bool wait_for_results(const std::string& out, std::size_t n, int timeout_ms) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (std::chrono::steady_clock::now() < deadline) {
      try {
        if (fs::exists(fx_.root() / out / "results.sqlite") && results(out).size() >= n) return true;
      } catch (const std::exception&) {
        // the orchestrator is creating the file
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  static std::map<std::int64_t, std::string> fingerprints(const std::vector<EpisodeRow>& rows) {
    std::map<std::int64_t, std::string> out;
    for (const auto& r : rows) out[r.episode_id.value()] = orchestrator::verdict_fingerprint(r);
    return out;
  }

  FixtureDataset fx_;
  BuiltScene built_;
  std::string tasks_db_;
};


}  // namespace mtg::testing
