#include "orchestrator/remote/session_rules.h"

#include <algorithm>

namespace mtg::orchestrator::remote {

std::optional<std::string> status_challenge(const std::string& command, const std::string& argument) {
  if (command != kStatusProbe || argument.empty() || argument.size() > 64) return std::nullopt;
  return argument;
}

bool CoordinatorSessions::holds(const std::deque<std::string>& sessions, const std::string& s) {
  return std::find(sessions.begin(), sessions.end(), s) != sessions.end();
}

void CoordinatorSessions::remember(std::deque<std::string>& sessions, const std::string& s) {
  if (holds(sessions, s)) return;
  sessions.push_back(s);
  if (sessions.size() > kKept) sessions.pop_front();
}

void CoordinatorSessions::left(const std::string& session) {
  if (!session.empty()) remember(left_, session);
}

OnAnnouncement CoordinatorSessions::hear(const HeardAnnouncement& m, const std::string& own_session,
                                         const std::string& run_id, const std::string& serving,
                                         const std::string& only_run) {
  if (m.session.empty() || (!only_run.empty() && m.run_id != only_run)) return OnAnnouncement::kIgnore;
  const bool was_over = holds(ended_, m.session) || holds(left_, m.session);
  if (m.done) remember(ended_, m.session);
  if (!run_id.empty()) {
    if (m.run_id != run_id) return OnAnnouncement::kIgnore;
    if (m.session == serving) return m.done ? OnAnnouncement::kLeave : OnAnnouncement::kStay;
  }
  if (m.done || was_over) return OnAnnouncement::kIgnore;
  // Only a live coordinator can name a session drawn after everything an attacker captured.
  if (std::find(m.heard.begin(), m.heard.end(), own_session) == m.heard.end()) return OnAnnouncement::kUnnamed;
  return run_id.empty() ? OnAnnouncement::kJoin : OnAnnouncement::kFollow;
}

OnGrant hear_grant(const std::string& session, int attempt, const std::string& serving, std::optional<int> held) {
  if (serving.empty() || session != serving) return OnGrant::kIgnore;
  if (!held) return OnGrant::kRun;
  if (attempt == *held) return OnGrant::kRenew;
  return attempt > *held ? OnGrant::kRun : OnGrant::kIgnore;
}

}  // namespace mtg::orchestrator::remote
