#pragma once
// `mtg leaderboard`: the agents of several runs ranked per suite, with what paired tests can
// tell apart (docs/statistics.md, "Leaderboard").

#include <string>
#include <vector>

namespace mtg::cli {

struct LeaderboardOptions {
  std::vector<std::string> runs;  // run folders
  bool json = false;              // print one JSON object instead of the tables
  std::string markdown;           // also write the boards as Markdown here ("" = no file)
};

int run_leaderboard(const LeaderboardOptions& options);

}  // namespace mtg::cli
