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

struct LeaseRecord {
  bus::EpisodeId episode_id;
  int attempt = 0;
  std::string worker;
};

class LeaseBook {
 public:
  explicit LeaseBook(const std::filesystem::path& file);
  void grant(const LeaseRecord& lease);
  /// state: "done" (result stored or ignored), "expired", "revoked".
  void close(bus::EpisodeId episode_id, int attempt, const std::string& state);
  /// Leases granted and not closed.
  std::vector<LeaseRecord> open_leases() const;
  /// Highest attempt granted per episode.
  std::map<bus::EpisodeId, int> last_attempts() const;

 private:
  std::unique_ptr<store::Database> db_;
};

}  // namespace mtg::orchestrator::remote
