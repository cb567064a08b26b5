#pragma once
// What a worker makes of what it hears from coordinators on the shared bus (docs/multihost.md,
// "Threat model"). Every coordinator and worker process draws a session token when it starts;
// announcements name the coordinator's session and the worker sessions it heard lately, grants
// and renewals name the coordinator session they belong to. An attacker without the key cannot
// sign, only re-send what it captured; these rules make a re-sent message worthless even to a
// process that never received it:
//   - a worker joins a run only from an announcement that names the worker's own session (no
//     announcement sent before the worker started can), never one of a session that announced
//     its end, or that this worker left for a newer session of the same run;
//   - a worker in a run follows a new session of that run (a resumed coordinator) only when it
//     names the worker, and never goes back to the one it left;
//   - a grant counts only from the session the worker serves, and never for an attempt older
//     than the one it holds of that episode.

#include <cstddef>
#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace mtg::orchestrator::remote {

/// `mtg status`'s challenge (run_control_t command, its nonce the argument): workers answer with a
/// heartbeat, coordinators with an announcement, that echo the nonce, and status believes only
/// those, so nothing sent before it asked (a dead worker's beats, a finished run's announcement,
/// replayed to a status that never heard them) is shown as alive.
inline constexpr const char* kStatusProbe = "status_probe";
/// The nonce a run_control_t (`command`, `argument`) asks to be echoed: the argument of a status
/// challenge, when it is one of at most 64 bytes; nullopt for any other message.
std::optional<std::string> status_challenge(const std::string& command, const std::string& argument);

struct HeardAnnouncement {
  std::string run_id;
  std::string session;             // the coordinator's
  bool done = false;               // state "done"
  std::vector<std::string> heard;  // worker sessions it names
};

enum class OnAnnouncement {
  kIgnore,  // not for this worker, a replay, or a session that is over
  kUnnamed, // a session this worker could join or follow that has not heard it yet: heartbeat now
  kJoin,    // an idle worker joins this run
  kStay,    // the run this worker serves, from its session: still there
  kFollow,  // the run this worker serves, from a newer session (a resumed coordinator)
  kLeave,   // the session this worker serves announced its end
};

class CoordinatorSessions {
 public:
  /// Sessions remembered as ended or left; past this the oldest are forgotten.
  static constexpr std::size_t kKept = 64;

  /// `run_id`/`serving`: the run and coordinator session this worker is in ("" = idle);
  /// `only_run`: the run it is bound to ("" = any). Remembers sessions that announce their end.
  OnAnnouncement hear(const HeardAnnouncement& m, const std::string& own_session, const std::string& run_id,
                      const std::string& serving, const std::string& only_run = "");
  /// The worker left `session` for a newer one of the same run: never back to it.
  void left(const std::string& session);
  /// Sessions remembered now (at most 2 × kKept).
  std::size_t remembered() const { return ended_.size() + left_.size(); }

 private:
  static bool holds(const std::deque<std::string>& sessions, const std::string& s);
  static void remember(std::deque<std::string>& sessions, const std::string& s);
  std::deque<std::string> ended_, left_;
};

enum class OnGrant {
  kIgnore,  // another session's, or an attempt older than the one held
  kRenew,   // the attempt held: the renewal was lost
  kRun,     // a new attempt (replacing an older one held, if any)
};

/// What a worker does with a grant of `attempt` from coordinator session `session`, serving
/// `serving` and holding attempt `held` of that episode (nullopt = none).
OnGrant hear_grant(const std::string& session, int attempt, const std::string& serving, std::optional<int> held);

}  // namespace mtg::orchestrator::remote
