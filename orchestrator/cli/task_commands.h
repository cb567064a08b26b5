#pragma once
// `mtg tasks ...`: generate task sets into SQLite (+ JSONL) and summarise them.

#include <cstdint>
#include <string>
#include <vector>

#include "agents/vlm/options.h"

namespace mtg::cli {

struct TasksOptions {
  std::vector<std::string> scenes;
  std::string data_dir;
  std::string out;                  // tasks.sqlite
  std::string jsonl;                // optional export
  std::uint64_t seed = 0;
  std::string levels = "1,2,3,4";
  std::string profile = "replica_cad";
  std::string ambiguity = "noun";
  std::string visibility = "on";  // off: the geometry alone decides (for comparisons; docs/tasks.md)
  int level3_count = 10000;
  int jobs = 0;  // threads (0: the machine's cores); the output does not depend on it
  int level3_chain = 2;
  int level4_max_moves = 3;
  double level4_max_kind_share = 0.2;
  std::string level4_templates = "builtin";
  std::string votes;                // recorded Level 4 votes (JSONL)
  std::vector<std::string> voters;  // model agents voting live on Level 4 candidates
  vlm::VlmOptions vlm;
  int step_limit = 15;
};

struct TaskStatsOptions {
  std::string db;
  bool json = false;
};

int run_tasks(const TasksOptions& options);
int run_task_stats(const TaskStatsOptions& options);

}  // namespace mtg::cli
