#pragma once
// leases.sqlite in a multi-host run folder: every lease the coordinator granted and what became
// of it. A restarted coordinator reads it to adopt the leases still out (their workers keep
// running them) and to number the next attempts above every one used before.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bus/episode_id.h"
#include "core/store/sqlite.h"

namespace mtg::orchestrator::remote {

/// What became of a lease; the book stores the name (to_string).
enum class LeaseState {
  kGranted,  // out: its worker runs it
  kDone,     // its result was stored or ignored
  kExpired,  // not renewed in time
  kRevoked,  // taken back (the episode runs elsewhere)
};
const char* to_string(LeaseState state);

struct LeaseRecord {
  bus::EpisodeId episode_id;
  int attempt = 0;
  std::string worker;
};

class LeaseBook {
 public:
  explicit LeaseBook(const std::filesystem::path& file);
  void grant(const LeaseRecord& lease);
  void close(bus::EpisodeId episode_id, int attempt, LeaseState state);
  /// Leases granted and not closed.
  std::vector<LeaseRecord> open_leases() const;
  /// Highest attempt granted per episode.
  std::map<bus::EpisodeId, int> last_attempts() const;

 private:
  std::unique_ptr<store::Database> db_;
};

}  // namespace mtg::orchestrator::remote
