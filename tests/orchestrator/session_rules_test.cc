// The rules by which a worker takes what it hears on the shared bus (session_rules.h): every
// replay an attacker without the key can make, to a worker that heard the original or not.

#include <gtest/gtest.h>

#include "orchestrator/remote/session_rules.h"

namespace mtg::orchestrator::remote {
namespace {

HeardAnnouncement running(const std::string& session, std::vector<std::string> heard, const std::string& run = "r1") {
  return {run, session, false, std::move(heard)};
}
HeardAnnouncement done(const std::string& session, const std::string& run = "r1") { return {run, session, true, {}}; }

// A worker started after a coordinator died hears that coordinator's announcements replayed:
// none of them can name the worker's session, drawn after they were sent.
TEST(SessionRulesTest, AnIdleWorkerJoinsOnlyAnAnnouncementThatNamesIt) {
  CoordinatorSessions s;
  EXPECT_EQ(s.hear(running("c1", {"old-worker"}), "w", "", ""), OnAnnouncement::kUnnamed);
  EXPECT_EQ(s.hear(running("c1", {}), "w", "", ""), OnAnnouncement::kUnnamed);
  EXPECT_EQ(s.hear(running("c1", {"other", "w"}), "w", "", ""), OnAnnouncement::kJoin);
  EXPECT_EQ(s.hear(running("", {"w"}), "w", "", ""), OnAnnouncement::kIgnore) << "no session: not a coordinator of ours";
  EXPECT_EQ(s.hear(running("c1", {"w"}), "w", "", "", "another-run"), OnAnnouncement::kIgnore);
}

TEST(SessionRulesTest, ASessionThatAnnouncedItsEndIsNeverJoinedAgain) {
  CoordinatorSessions s;
  EXPECT_EQ(s.hear(running("c1", {"w"}), "w", "r1", "c1"), OnAnnouncement::kStay);
  EXPECT_EQ(s.hear(done("c1"), "w", "r1", "c1"), OnAnnouncement::kLeave);
  // Back to idle: the same session's "running", even naming this worker (a straggler), is over.
  EXPECT_EQ(s.hear(running("c1", {"w"}), "w", "", ""), OnAnnouncement::kIgnore);
  // A resumed run is a new session and is joined.
  EXPECT_EQ(s.hear(running("c2", {"w"}), "w", "", ""), OnAnnouncement::kJoin);
}

// A resumed coordinator (same run, new session) takes over the workers of the run when it names
// them; the session it replaced is never followed again, whatever is replayed.
TEST(SessionRulesTest, AWorkerFollowsANewSessionOfItsRunAndNeverGoesBack) {
  CoordinatorSessions s;
  EXPECT_EQ(s.hear(running("c2", {"x"}), "w", "r1", "c1"), OnAnnouncement::kUnnamed) << "c2 has not heard w yet";
  EXPECT_EQ(s.hear(running("c2", {"w"}), "w", "r1", "c1"), OnAnnouncement::kFollow);
  s.left("c1");
  EXPECT_EQ(s.hear(running("c1", {"w"}), "w", "r1", "c2"), OnAnnouncement::kIgnore);
  EXPECT_EQ(s.hear(running("c2", {"w"}), "w", "r1", "c2"), OnAnnouncement::kStay);
  EXPECT_EQ(s.hear(running("c3", {"w"}, "r2"), "w", "r1", "c2"), OnAnnouncement::kIgnore) << "another run while in one";
  EXPECT_EQ(s.hear(done("c1"), "w", "r1", "c2"), OnAnnouncement::kIgnore) << "the end of a session left is not ours";
}

TEST(SessionRulesTest, RememberedSessionsAreBounded) {
  CoordinatorSessions s;
  for (std::size_t i = 0; i < 10 * CoordinatorSessions::kKept; ++i) {
    s.hear(done("c" + std::to_string(i)), "w", "", "");
    s.left("l" + std::to_string(i));
  }
  EXPECT_LE(s.remembered(), 2 * CoordinatorSessions::kKept);
  // The most recent are still known as over.
  const std::string last = "c" + std::to_string(10 * CoordinatorSessions::kKept - 1);
  EXPECT_EQ(s.hear(running(last, {"w"}), "w", "", ""), OnAnnouncement::kIgnore);
}

// An older grant (re-sent late, or replayed from the same session to a worker that missed it)
// never displaces the newer attempt a worker holds; a grant of another session is never taken.
TEST(SessionRulesTest, AnOlderGrantNeverDisplacesTheNewerAttemptHeld) {
  EXPECT_EQ(hear_grant("c1", 3, "c1", std::nullopt), OnGrant::kRun);
  EXPECT_EQ(hear_grant("c1", 3, "c1", 3), OnGrant::kRenew);
  EXPECT_EQ(hear_grant("c1", 4, "c1", 3), OnGrant::kRun);
  EXPECT_EQ(hear_grant("c1", 2, "c1", 3), OnGrant::kIgnore);
  EXPECT_EQ(hear_grant("c0", 9, "c1", std::nullopt), OnGrant::kIgnore);
  EXPECT_EQ(hear_grant("c1", 0, "", std::nullopt), OnGrant::kIgnore) << "a worker in no run takes no grant";
}

// What workers and coordinators answer: only mtg status's challenge, with a nonce of sensible size.
TEST(SessionRulesTest, OnlyAStatusChallengeWithANonceIsEchoed) {
  EXPECT_EQ(status_challenge(kStatusProbe, "3fa2c1d0"), std::optional<std::string>("3fa2c1d0"));
  EXPECT_EQ(status_challenge(kStatusProbe, std::string(64, 'a')), std::optional<std::string>(std::string(64, 'a')));
  EXPECT_EQ(status_challenge(kStatusProbe, std::string(65, 'a')), std::nullopt) << "an oversize nonce";
  EXPECT_EQ(status_challenge(kStatusProbe, ""), std::nullopt) << "no nonce";
  EXPECT_EQ(status_challenge("shutdown", "3fa2c1d0"), std::nullopt) << "another command";
}

}  // namespace
}  // namespace mtg::orchestrator::remote
