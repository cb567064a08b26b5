#pragma once
// `mtg gather RUN`: the recordings of a multi-host run that stayed where they were made
// (docs/multihost.md, "Recordings that stay where they are made") brought into the run folder,
// as episodes/E<id>-a<attempt>.lcmlog, each checked against the SHA-256 its reference holds;
// the references then name the copies, so the run folder alone holds the whole run. A recording
// comes from a shared folder (copied), from folders given with --from (a worker's folder copied
// by hand), or from the workers themselves over the run's shared bus (`mtg worker` still running
// on its host). What cannot be found is named with its host, and the command fails.

#include <filesystem>
#include <string>
#include <vector>

namespace mtg::orchestrator::remote {

struct GatherOptions {
  std::filesystem::path run;         // the run folder
  std::vector<std::filesystem::path> from;  // folders to look in first (a worker's --dir, copied)
  bool bus = true;                   // ask the workers for what is still missing
  std::string bus_url;               // "" = the run's (plan.json)
  std::string bus_key;               // "" = $MTG_BUS_KEY, else the run folder's bus.key
  double wait_s = 30.0;              // without a new recording arriving for this long, give up
};

struct GatherReport {
  int already = 0;    // in the run folder before
  int copied = 0;     // from a shared folder or --from
  int received = 0;   // from workers over the bus
  std::vector<std::string> missing;  // one line each (what, where it is kept)
  std::int64_t bytes = 0;            // copied or received
};

/// @throws mtg::Error naming the run folder when it holds no run, or a file it cannot write.
GatherReport gather_recordings(const GatherOptions& options);

}  // namespace mtg::orchestrator::remote
