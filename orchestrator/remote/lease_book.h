#pragma once
// leases.sqlite in a multi-host run folder: every lease the coordinator granted and what became
// of it. A restarted coordinator reads it to adopt the leases still out (their workers keep
// running them) and to number the next attempts above every one used before.
//
// Changes wait in the book until flush(), which writes them all in one transaction: a coordinator
// of many hosts grants and closes hundreds of leases a second, and a commit each was most of its
// CPU (docs/multihost.md, "A coordinator for 100 hosts"). The coordinator flushes before it sends
// the grants written, so a grant is on disk before it is out.

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
  /// Writes what is pending (a book dropped unflushed loses it, as a killed coordinator would).
  ~LeaseBook();
  void grant(const LeaseRecord& lease);
  void close(bus::EpisodeId episode_id, int attempt, LeaseState state);
  /// Writes every grant and close so far, in one transaction. @throws mtg::Error if it cannot.
  void flush();
  bool pending() const { return !pending_.empty(); }
  /// Leases granted and not closed (as written: flush first).
  std::vector<LeaseRecord> open_leases() const;
  /// Highest attempt granted per episode (as written).
  std::map<bus::EpisodeId, int> last_attempts() const;

 private:
  struct Change {
    LeaseRecord lease;
    LeaseState state = LeaseState::kGranted;
  };
  std::unique_ptr<store::Database> db_;
  std::unique_ptr<store::Statement> grant_, close_;  // prepared once
  std::vector<Change> pending_;
};

}  // namespace mtg::orchestrator::remote
