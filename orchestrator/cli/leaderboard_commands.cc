#include "orchestrator/cli/leaderboard_commands.h"

#include <filesystem>
#include <iostream>
#include <map>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "orchestrator/report/leaderboard.h"

namespace mtg::cli {

int run_leaderboard(const LeaderboardOptions& o) {
  if (o.runs.empty()) throw Error("no run folder given");
  std::vector<orchestrator::LeaderboardRun> runs;
  std::map<std::string, int> named;
  for (const std::string& dir : o.runs) {
    runs.push_back(orchestrator::load_leaderboard_run(dir));
    named[runs.back().name] += 1;
  }
  // Folders of one name in different places (a/run, b/run) are told apart by the path as given;
  // scripts/leaderboard-check names them the same way.
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (named[runs[i].name] > 1) runs[i].name = o.runs[i];
  }
  const nlohmann::json board = orchestrator::make_leaderboard(runs);
  if (!o.markdown.empty()) {
    // Renamed over the target, so a link at that path is replaced, never written through.
    write_file_atomically(o.markdown, [&](std::ostream& out) { out << orchestrator::leaderboard_markdown(board); });
  }
  if (o.json) {
    std::cout << board.dump() << '\n';
  } else {
    std::cout << orchestrator::leaderboard_text(board);
    if (!o.markdown.empty()) std::cout << "wrote " << o.markdown << '\n';
  }
  return 0;
}

}  // namespace mtg::cli
