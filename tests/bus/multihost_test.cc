// Multi-host runs with real processes on simulated hosts: network namespaces joined by veth
// pairs to a bridge (scripts/netns-hosts), each running `mtg worker`; the coordinator
// (`mtg run --remote`) runs in this test's own namespace. The hosts are made and removed here.

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sched.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <map>
#include <thread>

#include "bus/authenticator.h"
#include "bus/bus.h"
#include "bus/header.h"
#include "bus/recording_ref.h"
#include "bus/url.h"
#include "core/util/sha256.h"
#include "mtg/episode_result_t.hpp"
#include "mtg/heartbeat_t.hpp"
#include "mtg/lease_t.hpp"
#include "mtg/observation_t.hpp"
#include "mtg/recording_ref_t.hpp"
#include "mtg/run_control_t.hpp"
#include "mtg/run_info_t.hpp"
#include "orchestrator/run/run_plan.h"
#include "tests/bus/multihost_fixture.h"
#include "tests/support/fake_model_server.h"

namespace mtg {
namespace {

using testing_multihost::kSharedUrl;
using testing_multihost::MultiHostTest;
namespace fs = std::filesystem;
using orchestrator::EpisodeRow;

TEST_F(MultiHostTest, TwoAndThreeHostsGiveTheResultsOfOneHostAndTheRecordingRejudgesTheSame) {
  ASSERT_EQ(mtg(run_args("one", 3, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));
  ASSERT_EQ(single.size(), planned("one"));

  make_hosts(3);
  for (const int n : {2, 3}) {
    const std::string out = "hosts" + std::to_string(n);
    for (int i = 0; i < n; ++i) start_worker(i);
    ASSERT_EQ(mtg(run_args(out, 3, 4, n)), 0) << log_text();
    const auto rows = results(out);
    EXPECT_EQ(fingerprints(rows), single) << n << " hosts";
    std::set<std::string> used;
    for (const auto& r : rows) used.insert(r.worker);
    EXPECT_EQ(used.size(), static_cast<std::size_t>(n)) << "the run spread over every host";
    expect_one_start_per_episode(out);
    testing::ChildProcess rejudge({testing::bin("mtg"), "rejudge", (fx_.root() / out).string()}, log());
    EXPECT_EQ(rejudge.wait(60000), 0) << log_text();
    EXPECT_NE(log_text().find(std::to_string(rows.size()) + " identical, 0 differ"), std::string::npos) << log_text();
    workers_.clear();  // next round: fresh workers
  }
  // The multi-host run replays on this machine alone, with no worker left (before, `mtg replay`
  // waited for workers on the shared bus).
  testing::ChildProcess replay({testing::bin("mtg"), "replay", (fx_.root() / "hosts3").string()}, log());
  EXPECT_EQ(replay.wait(60000), 0) << log_text();
  const std::string rows = std::to_string(results("hosts3").size());
  EXPECT_NE(log_text().find(rows + " / " + rows + " judge results identical"), std::string::npos) << log_text();
}

// Recordings that stay where they are made (--recordings shared:PATH | worker): only a reference
// with the file's SHA-256 crosses the shared bus, no chunk; the run folder's tools read the run as
// they read a merged one (rejudge identical, the same images, one start per episode); a damaged or
// missing recording is named; recordings kept on the workers come into the run folder with
// `mtg gather` over the bus, named while they are not there.
TEST_F(MultiHostTest, RecordingsKeptInASharedFolderOrOnTheWorkersReadAsAMergedOne) {
  make_hosts(2);
  for (int i = 0; i < 2; ++i) start_worker(i);
  bus::Bus tap(kSharedUrl);  // counts what crosses the shared bus
  std::map<std::string, std::pair<int, std::int64_t>> crossing;  // channel -> (messages, bytes)
  tap.subscribe_raw(".*", [&](const std::string& channel, std::span<const std::uint8_t> b, std::int64_t) {
    ++crossing[channel].first;
    crossing[channel].second += static_cast<std::int64_t>(b.size());
  });
  const auto run = [&](const std::string& out, const std::vector<std::string>& extra) {
    crossing.clear();
    std::vector<std::string> args = run_args(out, 3, 4, 2);
    args.insert(args.end(), extra.begin(), extra.end());
    testing::ChildProcess p(args, log());
    while (p.running()) tap.handle_once(20);
    EXPECT_EQ(p.wait(1000), 0) << log_text();
    while (tap.handle_once(50)) {
    }
  };
  const auto rejudge = [&](const std::string& out) {
    const fs::path text = fx_.root() / ("rejudge-" + out + ".txt");
    testing::ChildProcess p({testing::bin("mtg"), "rejudge", (fx_.root() / out).string()}, text.string());
    const int status = p.wait(60000);
    return std::make_pair(status, testing_multihost::read_text(text));
  };
  const auto images = [&](const std::string& out) {
    const fs::path folder = fx_.root() / ("images-" + out);
    testing::ChildProcess p({testing::bin("mtg"), "images", (fx_.root() / out).string(), "--out", folder.string()}, log());
    EXPECT_EQ(p.wait(60000), 0) << log_text();
    std::set<std::string> names;
    for (const auto& f : fs::directory_iterator(folder)) names.insert(f.path().filename().string());
    return names;
  };

  run("merged", {"--render", "--image-size", "160x120"});
  const auto merged = fingerprints(results("merged"));
  EXPECT_GT(crossing[bus::kRecord].first, 0);
  const std::int64_t merged_bytes = crossing[bus::kRecord].second;

  const fs::path shared = fx_.root() / "shared";
  run("shared", {"--render", "--image-size", "160x120", "--recordings", "shared:" + shared.string()});
  EXPECT_EQ(fingerprints(results("shared")), merged);
  EXPECT_EQ(crossing.count(bus::kRecord), 0u) << "no recording chunk crosses the bus";
  EXPECT_EQ(crossing[bus::kRecordRef].first, static_cast<int>(merged.size()) * 1) << "one reference per attempt";
  EXPECT_LT(crossing[bus::kRecordRef].second * 100, merged_bytes) << "references are small";
  const std::string run_id = orchestrator::load_plan(fx_.root() / "shared").run_id;
  EXPECT_TRUE(fs::exists(shared / run_id / "shared.probe"));
  EXPECT_FALSE(fs::exists(fx_.root() / "shared" / "bus-merged.lcmlog"));
  EXPECT_FALSE(fs::exists(fx_.root() / "shared" / "episodes")) << "nothing of it came to the coordinator";
  const auto refs = bus::read_recording_refs(fx_.root() / "shared" / "results.sqlite");
  ASSERT_EQ(refs.size(), merged.size());
  for (const auto& r : refs) {
    EXPECT_TRUE(r.shared);
    EXPECT_TRUE(fs::exists(shared / run_id / fs::path(r.location).filename())) << r.location;
  }
  expect_one_start_per_episode("shared");
  {
    const auto [status, text] = rejudge("shared");
    EXPECT_EQ(status, 0) << text;
    EXPECT_NE(text.find(std::to_string(merged.size()) + " identical, 0 differ"), std::string::npos) << text;
  }
  EXPECT_EQ(images("shared"), images("merged")) << "the same images from either";
  {
    // Replayed on this machine, and exported as a site (the viewer's reading of it).
    const fs::path text = fx_.root() / "replay-shared.txt";
    testing::ChildProcess replay({testing::bin("mtg"), "replay", (fx_.root() / "shared").string()}, text.string());
    EXPECT_EQ(replay.wait(120000), 0) << testing_multihost::read_text(text);
    const std::string n = std::to_string(merged.size());
    EXPECT_NE(testing_multihost::read_text(text).find(n + " / " + n + " judge results identical"), std::string::npos)
        << testing_multihost::read_text(text);
    // The same site from either run: as many episode pages and image files.
    const auto site_files = [&](const std::string& out) {
      const fs::path site = fx_.root() / ("site-" + out);
      testing::ChildProcess exported({testing::bin("mtg"), "export", (fx_.root() / out).string(), "--out", site.string()},
                                     text.string());
      EXPECT_EQ(exported.wait(120000), 0) << testing_multihost::read_text(text);
      std::size_t files = 0;
      for (const auto& f : fs::recursive_directory_iterator(site)) files += f.is_regular_file() ? 1 : 0;
      return files;
    };
    const std::size_t exported = site_files("shared");
    EXPECT_EQ(exported, site_files("merged"));
    EXPECT_GT(exported, merged.size());
    EXPECT_EQ(testing_multihost::read_text(text).find("damaged"), std::string::npos) << testing_multihost::read_text(text);
  }

  // Damage is named, file by file: one recording flipped, one gone.
  const fs::path first = bus::resolve(refs[0], fx_.root() / "shared");
  const fs::path second = bus::resolve(refs[1], fx_.root() / "shared");
  {
    std::fstream f(first, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(40);
    f.put('\x7f');
  }
  fs::rename(second, second.string() + ".away");
  {
    const auto [status, text] = rejudge("shared");
    EXPECT_NE(status, 0) << text;
    EXPECT_NE(text.find(first.string() + " is damaged"), std::string::npos) << text;
    EXPECT_NE(text.find(second.string() + " is missing from the shared folder"), std::string::npos) << text;
    // Each episode it could not judge is named with its own file's problem, not another's.
    for (const auto& r : {refs[0], refs[1]}) {
      const std::string n = to_string(r.episode), a = std::to_string(r.attempt);
      EXPECT_NE(text.find("lacks the start of episode " + n + " attempt " + a +
                          " (the recording is damaged: the recording of episode " + n + " (attempt " + a + ")"),
                std::string::npos)
          << text;
    }
  }

  // Kept on the workers: named while they are away, gathered over the bus, then whole.
  run("kept", {"--recordings", "worker"});
  EXPECT_EQ(crossing.count(bus::kRecord), 0u);
  const auto kept = bus::read_recording_refs(fx_.root() / "kept" / "results.sqlite");
  ASSERT_EQ(kept.size(), results("kept").size());
  std::set<std::string> hosts;
  for (const auto& r : kept) {
    EXPECT_FALSE(r.shared);
    hosts.insert(r.host);
  }
  EXPECT_EQ(hosts, (std::set<std::string>{"host0", "host1"}));
  // The folders are on this machine too; away, as on real hosts, the reader names what it lacks.
  for (int i = 0; i < 2; ++i) fs::rename(fx_.root() / ("worker" + std::to_string(i)), fx_.root() / ("away" + std::to_string(i)));
  {
    const auto [status, text] = rejudge("kept");
    EXPECT_NE(status, 0) << text;
    EXPECT_NE(text.find("kept on host1; `mtg gather` brings it into the run folder"), std::string::npos) << text;
  }
  for (int i = 0; i < 2; ++i) fs::rename(fx_.root() / ("away" + std::to_string(i)), fx_.root() / ("worker" + std::to_string(i)));
  const fs::path gathered = fx_.root() / "gather.txt";
  testing::ChildProcess gather({testing::bin("mtg"), "gather", (fx_.root() / "kept").string(), "--wait", "20"},
                               gathered.string());
  EXPECT_EQ(gather.wait(60000), 0) << testing_multihost::read_text(gathered);
  EXPECT_NE(testing_multihost::read_text(gathered).find("0 copied, " + std::to_string(kept.size()) + " received from workers"),
            std::string::npos)
      << testing_multihost::read_text(gathered);
  for (const auto& r : bus::read_recording_refs(fx_.root() / "kept" / "results.sqlite")) {
    EXPECT_EQ(r.location.rfind("episodes/", 0), 0u) << r.location << ": the run folder's own copy";
  }
  for (int i = 0; i < 2; ++i) fs::remove_all(fx_.root() / ("worker" + std::to_string(i)));
  {
    const auto [status, text] = rejudge("kept");
    EXPECT_EQ(status, 0) << text;
    EXPECT_NE(text.find(std::to_string(kept.size()) + " identical, 0 differ"), std::string::npos) << text;
  }
  // A worker that cannot write the shared folder (here: directories where episode 0 and 1's files
  // go) sends those recordings to the coordinator instead; the run is whole all the same.
  {
    const fs::path blocked = fx_.root() / "blocked";
    std::vector<std::string> args = run_args("fallback", 3, 4, 2);
    args.insert(args.end(), {"--recordings", "shared:" + blocked.string()});
    testing::ChildProcess p(args, log());
    ASSERT_TRUE(wait_for([&] { return fs::exists(fx_.root() / "fallback" / "plan.json"); }, 30000));
    const std::string id = orchestrator::load_plan(fx_.root() / "fallback").run_id;
    for (const char* name : {"E0-a0.lcmlog", "E1-a0.lcmlog"}) fs::create_directories(blocked / id / name / "in-the-way");
    EXPECT_EQ(p.wait(180000), 0) << log_text();
    EXPECT_EQ(fingerprints(results("fallback")), fingerprints(results("kept")));
    const auto refs_fallback = bus::read_recording_refs(fx_.root() / "fallback" / "results.sqlite");
    ASSERT_EQ(refs_fallback.size(), results("fallback").size());
    EXPECT_EQ(refs_fallback[0].location, "episodes/E0-a0.lcmlog");
    EXPECT_EQ(refs_fallback[2].location.rfind(blocked.string(), 0), 0u) << refs_fallback[2].location;
    EXPECT_NE(log_text().find("sending it to the coordinator instead"), std::string::npos);
    const auto [status, text] = rejudge("fallback");
    EXPECT_EQ(status, 0) << text;
  }

}

// A key holder forges signed recording references (issue 55: /etc/passwd, with its real size and
// hash, was once kept as four episodes' recordings and copied by gather). Impersonating the worker
// each attempt is leased to, it names a secret file, a 3 GB sparse file named like a recording
// outside the run's shared folder, and a path through ".."; as a key holder that holds no lease, the
// secret again. None is kept: every stored reference is the attempt's own file in the shared
// folder, the verdicts are a run's without the forger, and gather and rejudge read only those.
TEST_F(MultiHostTest, AKeyHolderForgingRecordingReferencesGetsNoFileKept) {
  ASSERT_EQ(mtg(run_args("one", 3, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));
  make_hosts(2);
  for (int i = 0; i < 2; ++i) start_worker(i);
  const fs::path shared = fx_.root() / "shared-forged";
  const fs::path secret = fx_.root() / "secret.txt";
  std::ofstream(secret, std::ios::binary) << "root:x:0:0:root:/root:/bin/bash\n";
  const std::string secret_text = testing_multihost::read_text(secret);
  bus::Bus forger(kSharedUrl);
  forger.authenticate(std::make_shared<const bus::Authenticator>(bus::Authenticator::read_secret(fx_.root() / "bus.key")));
  std::set<std::string> granted;
  std::map<std::string, int> sent;  // variant -> forged references sent
  std::string run_id;
  forger.subscribe<mtg::lease_t>(std::string(bus::kLease) + "_.*", [&](const std::string&, const mtg::lease_t& m) {
    if (m.action != "grant" || m.header.run_id.empty() || !granted.insert(m.lease_id).second) return;
    run_id = m.header.run_id;
    const std::int64_t episode = m.header.episode_id;
    mtg::recording_ref_t ref{};
    ref.header = m.header;  // this build's schema, the attempt the grant names
    ref.header.seq = 0;
    ref.header.episode_id = episode;
    ref.header.attempt = m.header.attempt;
    ref.header.sender = m.worker;  // as the worker holding the lease
    ref.lease_id = m.lease_id;
    ref.host = "host0";
    ref.shared = true;
    ref.bytes = static_cast<std::int64_t>(secret_text.size());
    ref.sha256 = sha256_hex(secret_text);
    const std::string name = "E" + std::to_string(episode) + "-a" + std::to_string(m.header.attempt) + ".lcmlog";
    std::string variant;
    switch (episode % 4) {
      case 0:
        variant = "secret";
        ref.location = secret.string();
        break;
      case 1: {
        variant = "sparse";
        const fs::path elsewhere = fx_.root() / "elsewhere" / run_id;
        fs::create_directories(elsewhere);
        ref.location = (elsewhere / name).string();
        std::ofstream(ref.location, std::ios::binary).close();
        fs::resize_file(ref.location, std::uintmax_t{3} << 30);
        ref.bytes = std::int64_t{3} << 30;
        break;
      }
      case 2:
        variant = "dotdot";
        ref.location = (shared / run_id).string() + "/../" + run_id + "/" + name;
        break;
      default:
        variant = "not the holder";
        ref.header.sender = "forger-0";
        ref.location = secret.string();
        break;
    }
    forger.publish(bus::kRecordRef, ref);
    ++sent[variant];
  });
  std::vector<std::string> args = run_args("forged-refs", 3, 4, 2);
  args.insert(args.end(), {"--recordings", "shared:" + shared.string()});
  testing::ChildProcess run(args, log());
  while (run.running()) forger.handle_once(20);
  ASSERT_EQ(run.wait(1000), 0) << log_text();
  EXPECT_EQ(fingerprints(results("forged-refs")), single);
  for (const char* v : {"secret", "sparse", "dotdot", "not the holder"}) EXPECT_GT(sent[v], 0) << v;
  const std::string text = log_text();
  EXPECT_NE(text.find("is not in this run's shared folder"), std::string::npos) << text;
  EXPECT_NE(text.find("is not an absolute path without . or .."), std::string::npos) << text;
  EXPECT_NE(text.find("which does not hold its lease; ignored"), std::string::npos) << text;
  const fs::path dir = fx_.root() / "forged-refs";
  const auto refs = bus::read_recording_refs(dir / "results.sqlite");
  ASSERT_EQ(refs.size(), single.size());
  for (const auto& r : refs) {
    const std::string name = "E" + to_string(r.episode) + "-a" + std::to_string(r.attempt) + ".lcmlog";
    EXPECT_EQ(bus::resolve(r, dir), shared / run_id / name) << r.location;
    EXPECT_NE(testing_multihost::read_text(bus::resolve(r, dir)), secret_text);
  }
  // gather copies the run's own files only; rejudge reads them all.
  const fs::path gathered = fx_.root() / "gather-forged.txt";
  testing::ChildProcess gather({testing::bin("mtg"), "gather", dir.string(), "--no-bus"}, gathered.string());
  EXPECT_EQ(gather.wait(60000), 0) << testing_multihost::read_text(gathered);
  if (fs::exists(dir / "episodes")) {
    for (const auto& f : fs::directory_iterator(dir / "episodes")) {
      EXPECT_NE(testing_multihost::read_text(f.path()), secret_text) << f.path();
    }
  }
  const fs::path rejudged = fx_.root() / "rejudge-forged.txt";
  testing::ChildProcess rejudge({testing::bin("mtg"), "rejudge", dir.string()}, rejudged.string());
  EXPECT_EQ(rejudge.wait(60000), 0) << testing_multihost::read_text(rejudged);
  EXPECT_NE(testing_multihost::read_text(rejudged).find(std::to_string(single.size()) + " identical, 0 differ"),
            std::string::npos)
      << testing_multihost::read_text(rejudged);
}

// A fresh `mtg status` believes only what answers its own challenge: a dead worker's heartbeats,
// captured and re-sent at it, do not list that worker (before, it was listed as idle).
TEST_F(MultiHostTest, AFreshStatusListsNoDeadWorkerWhoseBeatsAreReplayed) {
  make_hosts(2);
  for (int i = 0; i < 2; ++i) start_worker(i);
  bus::Bus tap(kSharedUrl);  // no key: it reads and re-sends datagrams as they are
  std::vector<std::vector<std::uint8_t>> beats;
  tap.subscribe_raw(bus::kHeartbeat, [&](const std::string&, std::span<const std::uint8_t> b, std::int64_t) {
    mtg::heartbeat_t hb{};
    if (hb.decode(b.data(), 0, static_cast<int>(b.size())) >= 0 && hb.host == "host1") beats.emplace_back(b.begin(), b.end());
  });
  ASSERT_TRUE(wait_for([&] {
    tap.handle_once(20);
    return beats.size() >= 4;
  }, 30000));
  kill_host(1);
  const fs::path out = fx_.root() / "status.json";
  testing::ChildProcess status({testing::bin("mtg"), "status", "--bus", kSharedUrl, "--json", "--listen", "3"},
                               out.string());
  std::size_t next = 0;
  while (status.running()) {
    tap.publish_raw(bus::kHeartbeat, beats[next++ % beats.size()]);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(status.wait(1000), 0) << testing_multihost::read_text(out);
  const std::string text = testing_multihost::read_text(out);
  const auto j = nlohmann::json::parse(text.substr(text.find('{')));
  std::set<std::string> hosts;
  for (const auto& w : j["workers"]) hosts.insert(w["host"].get<std::string>());
  EXPECT_EQ(hosts, (std::set<std::string>{"host0"})) << text;
  EXPECT_GE(j["unanswered"].get<int>(), 1) << text;
}

// The shared bus is authenticated: results, lease revocations and a shutdown forged during a run
// (unsigned, or signed with another key) are dropped and counted, and the run's results are those
// of one machine.
TEST_F(MultiHostTest, ForgedMessagesOnTheSharedBusAreDroppedAndCounted) {
  ASSERT_EQ(mtg(run_args("one", 4, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));
  make_hosts(2);
  for (int i = 0; i < 2; ++i) start_worker(i);
  testing::ChildProcess run(run_args("forged", 4, 4, 2), log());
  ASSERT_TRUE(wait_for([&] { return fs::exists(fx_.root() / "forged" / "plan.json"); }, 30000));
  const std::string run_id = orchestrator::load_plan(fx_.root() / "forged").run_id;
  bus::Bus plain(kSharedUrl);
  bus::Bus other_key(kSharedUrl);
  other_key.authenticate(std::make_shared<const bus::Authenticator>("not-the-run-s-secret-at-all"));
  // Lease messages go to each worker's own channel, named by the session its heartbeats show.
  std::set<std::string> sessions;
  plain.subscribe<mtg::heartbeat_t>(bus::kHeartbeat, [&](const std::string&, const mtg::heartbeat_t& m) {
    if (m.role == "worker" && !m.session.empty()) sessions.insert(m.session);
  });
  int forged = 0;
  while (run.running() && forged < 400) {
    while (plain.handle_once(0)) {
    }
    for (bus::Bus* b : {&plain, &other_key}) {
      mtg::episode_result_t fake{};
      fake.header.run_id = run_id;
      fake.header.episode_id = forged % 16;
      fake.success = true;
      fake.stage = "done";
      b->publish(bus::kEpisodeResult, fake);
      mtg::lease_t revoke{};
      revoke.header = fake.header;
      revoke.action = "revoke";
      b->publish(bus::kLease, revoke);
      for (const std::string& session : sessions) b->publish(bus::lease_channel(session), revoke);
      forged += 2;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(run.wait(180000), 0) << log_text();
  EXPECT_EQ(fingerprints(results("forged")), single);
  EXPECT_GT(forged, 0);
  EXPECT_NE(log_text().find("had no valid signature"), std::string::npos) << log_text();
}

// Junk on the shared bus names a new run id in every datagram: each is checked (and dropped), and
// the keys derived for them do not pile up.
TEST(AuthenticatorTest, JunkRunIdsAreDroppedWithoutGrowingItsMemory) {
  const bus::Authenticator auth("the-run-s-secret-of-this-test");
  for (int i = 0; i < 5000; ++i) {
    mtg::heartbeat_t junk{};
    junk.header.run_id = "junk-" + std::to_string(i);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(junk.getEncodedSize()) + bus::Authenticator::kTrailerBytes);
    junk.encode(bytes.data(), 0, junk.getEncodedSize());
    EXPECT_FALSE(auth.verify("MTG_HEARTBEAT", bytes));  // a tag of zeros
  }
  EXPECT_EQ(auth.rejected(), 5000);
  EXPECT_LE(auth.run_keys_kept(), 64u);
  // A signed message of a real run still passes.
  mtg::heartbeat_t real{};
  real.header.run_id = "run-1";
  std::vector<std::uint8_t> payload(static_cast<std::size_t>(real.getEncodedSize()));
  real.encode(payload.data(), 0, real.getEncodedSize());
  EXPECT_TRUE(auth.verify("MTG_HEARTBEAT", auth.sign("MTG_HEARTBEAT", payload)));
}

// An attacker without the key re-sends signed datagrams it captured on the shared bus: a finished
// run's announcements at idle workers, and, once a worker is killed mid-run, that worker's
// heartbeats every 0.5 s. The receivers took each of them before: they are dropped as replays,
// the workers stay free for the next run, no lease goes to the dead worker after its leases
// expire, and the run gives the one-host verdicts with no episode given up.
TEST_F(MultiHostTest, ReplayedDatagramsOfAFinishedRunOrAKilledWorkerChangeNothing) {
  ASSERT_EQ(mtg(run_args("one", 8, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));
  make_hosts(2);
  for (int i = 0; i < 2; ++i) start_worker(i);

  bus::Bus tap(kSharedUrl);  // no key: it reads and re-sends datagrams as they are
  std::vector<std::vector<std::uint8_t>> announcements, beats;
  bool capture_beats = false;
  tap.subscribe_raw(bus::kRunInfo, [&](const std::string&, std::span<const std::uint8_t> b, std::int64_t) {
    announcements.emplace_back(b.begin(), b.end());
  });
  tap.subscribe_raw(bus::kHeartbeat, [&](const std::string&, std::span<const std::uint8_t> b, std::int64_t) {
    mtg::heartbeat_t hb{};
    if (capture_beats && hb.decode(b.data(), 0, static_cast<int>(b.size())) >= 0 && hb.host == "host1") {
      beats.emplace_back(b.begin(), b.end());
    }
  });
  // Grants carry the episode's answers: sealed, so the tap (no key) reads no goal or plan.
  int grants = 0, open_grants = 0;
  tap.subscribe_raw("MTG_LEASE.*", [&](const std::string&, std::span<const std::uint8_t> b, std::int64_t) {
    mtg::lease_t m{};
    if (m.decode(b.data(), 0, static_cast<int>(b.size())) < 0 || m.action != "grant") return;
    ++grants;
    if (!bus::is_sealed(m.truth) || !m.truth.goal_json.empty() || !m.truth.oracle_plan.empty()) ++open_grants;
  });
  auto pump = [&](testing::ChildProcess& run) {
    while (run.running()) tap.handle_once(50);
  };
  {
    testing::ChildProcess first(run_args("first", 4, 4, 2), log());
    pump(first);
    ASSERT_EQ(first.wait(1000), 0) << log_text();
  }
  ASSERT_FALSE(announcements.empty());
  EXPECT_GT(grants, 0);
  EXPECT_EQ(open_grants, 0) << "grants with answers in clear on the shared bus";
  // The finished run's announcements ("running" included), re-sent at the idle workers.
  for (int round = 0; round < 4; ++round) {
    for (const auto& a : announcements) tap.publish_raw(bus::kRunInfo, a);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  // The next run still gets both workers, and host 1's heartbeats of this run are captured.
  testing::ChildProcess run(run_args("replayed", 8, 4, 2), log());
  capture_beats = true;
  ASSERT_TRUE(wait_for([&] {
    tap.handle_once(20);
    return results("replayed").size() >= 2 && beats.size() >= 4;
  }, 60000)) << log_text();
  capture_beats = false;
  kill_host(1);
  auto last = std::chrono::steady_clock::now();
  std::size_t next = 0;
  while (run.running()) {
    tap.handle_once(20);
    if (std::chrono::steady_clock::now() - last > std::chrono::milliseconds(500)) {
      tap.publish_raw(bus::kHeartbeat, beats[next++ % beats.size()]);
      last = std::chrono::steady_clock::now();
    }
  }
  ASSERT_EQ(run.wait(1000), 0) << log_text();
  const auto rows = results("replayed");
  EXPECT_EQ(rows.size(), planned("replayed"));
  EXPECT_EQ(fingerprints(rows), single);
  for (const auto& r : rows) EXPECT_EQ(r.status, "scored") << r.task_id << ": " << r.detail;
  EXPECT_NE(log_text().find("were replays"), std::string::npos) << log_text();
}

// Replays to processes that never received the originals. A coordinator killed and resumed with
// the same run id is a new process: before, it took the killed host's heartbeats of the first
// invocation, re-sent every 0.5 s, as new, leased episodes to the dead host and ran them again
// when the leases expired. Workers started after a run ended are new processes too: before, the
// run's "running" announcements re-sent at them pulled them into that run. The first
// invocation's grants are re-sent into the resumed run too. Now heartbeats and renewals name the
// coordinator session they serve, grants name theirs, and a worker joins only an announcement
// that names its own session: no lease goes to the dead host, the fresh workers stay free, and
// both runs give the one-host verdicts.
TEST_F(MultiHostTest, ReplaysToProcessesStartedAfterTheMessagesChangeNothing) {
  ASSERT_EQ(mtg(run_args("one", 40, 4, 0)), 0) << log_text();  // long enough to be killed mid-run
  const auto single = fingerprints(results("one"));
  make_hosts(2);
  for (int i = 0; i < 2; ++i) start_worker(i);

  bus::Bus tap(kSharedUrl);  // no key: it reads and re-sends datagrams as they are
  std::vector<std::vector<std::uint8_t>> running, beats;
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> grants;  // (channel, datagram)
  bool capture_beats = true;
  tap.subscribe_raw("MTG_LEASE.*", [&](const std::string& channel, std::span<const std::uint8_t> b, std::int64_t) {
    mtg::lease_t m{};
    if (capture_beats && m.decode(b.data(), 0, static_cast<int>(b.size())) >= 0 && m.action == "grant") {
      grants.emplace_back(channel, std::vector<std::uint8_t>(b.begin(), b.end()));
    }
  });
  tap.subscribe_raw(bus::kRunInfo, [&](const std::string&, std::span<const std::uint8_t> b, std::int64_t) {
    mtg::run_info_t m{};
    if (m.decode(b.data(), 0, static_cast<int>(b.size())) >= 0 && m.state == "running") running.emplace_back(b.begin(), b.end());
  });
  std::string dead_worker;
  tap.subscribe_raw(bus::kHeartbeat, [&](const std::string&, std::span<const std::uint8_t> b, std::int64_t) {
    mtg::heartbeat_t hb{};
    if (capture_beats && hb.decode(b.data(), 0, static_cast<int>(b.size())) >= 0 && hb.host == "host1" &&
        !hb.header.run_id.empty()) {
      beats.emplace_back(b.begin(), b.end());
      dead_worker = hb.header.sender;
    }
  });
  auto leases_of = [&](const std::string& worker) {
    int n = 0;
    for (const auto state : {orchestrator::remote::LeaseState::kGranted, orchestrator::remote::LeaseState::kDone,
                             orchestrator::remote::LeaseState::kRevoked, orchestrator::remote::LeaseState::kExpired}) {
      const auto m = leases_in_state("resumed", state);
      const auto it = m.find(worker);
      n += it == m.end() ? 0 : it->second;
    }
    return n;
  };
  const auto args = run_args("resumed", 40, 4, 2);
  {
    testing::ChildProcess first(args, log());
    ASSERT_TRUE(wait_for([&] {
      tap.handle_once(20);
      return results("resumed").size() >= 2 && beats.size() >= 2;
    }, 60000)) << log_text();
    ASSERT_LT(results("resumed").size(), planned("resumed")) << "the run ended before it could be killed";
    capture_beats = false;
    kill_host(1);
    first.kill(SIGKILL);
  }
  const int granted_to_dead = leases_of(dead_worker);
  ASSERT_FALSE(grants.empty());
  // Resumed (a new coordinator process, same run id) while the dead host's heartbeats and the
  // first invocation's grants are re-sent; one worker is left.
  {
    testing::ChildProcess resumed(run_args("resumed", 40, 4, 1), log());
    auto last = std::chrono::steady_clock::now();
    std::size_t next = 0;
    while (resumed.running()) {
      tap.handle_once(20);
      if (std::chrono::steady_clock::now() - last > std::chrono::milliseconds(500)) {
        tap.publish_raw(bus::kHeartbeat, beats[next % beats.size()]);
        const auto& [channel, grant] = grants[next % grants.size()];
        tap.publish_raw(channel, grant);
        ++next;
        last = std::chrono::steady_clock::now();
      }
    }
    ASSERT_EQ(resumed.wait(1000), 0) << log_text();
  }
  EXPECT_EQ(leases_of(dead_worker), granted_to_dead) << "the resumed coordinator leased episodes to the dead host";
  auto rows = results("resumed");
  EXPECT_EQ(rows.size(), planned("resumed"));
  EXPECT_EQ(fingerprints(rows), single);
  for (const auto& r : rows) EXPECT_EQ(r.status, "scored") << r.task_id << ": " << r.detail;

  // Fresh workers on both hosts; the finished run's "running" announcements re-sent at them.
  kill_host(0);
  std::map<int, std::size_t> said_before;  // the worker logs are appended to
  for (int i = 0; i < 2; ++i) {
    said_before[i] = testing_multihost::read_text(fx_.root() / ("worker" + std::to_string(i) + ".log")).size();
    start_worker(i);
  }
  for (const int i : {0, 1}) {
    const fs::path log = fx_.root() / ("worker" + std::to_string(i) + ".log");
    ASSERT_TRUE(wait_for([&] {
      return testing_multihost::read_text(log).find(", capacity ", said_before[i]) != std::string::npos;
    }, 15000)) << log_text();
  }
  ASSERT_FALSE(running.empty());
  for (int round = 0; round < 4; ++round) {
    for (const auto& a : running) tap.publish_raw(bus::kRunInfo, a);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  for (const int i : {0, 1}) {
    const std::string said =
        testing_multihost::read_text(fx_.root() / ("worker" + std::to_string(i) + ".log")).substr(said_before[i]);
    EXPECT_EQ(said.find("joining run"), std::string::npos) << "host " << i << " joined a replayed run:\n" << said;
  }
  ASSERT_EQ(mtg(run_args("after", 4, 4, 2)), 0) << log_text();
  rows = results("after");
  EXPECT_EQ(rows.size(), planned("after"));
  std::set<std::string> used;
  for (const auto& r : rows) used.insert(r.worker);
  EXPECT_EQ(used.size(), 2u) << "both fresh workers served the next run";
}

// An attacker on the hosts' network (the bridge, without the bus key) reads the run id off the
// shared bus and sprays a shutdown and a forged success of every episode at every UDP port of a
// worker while it runs; a process on the worker's own host does the same at every port of its
// loopback address and of the host bus's group. A worker's host bus is a ttl=0 group, but liblcm
// binds 0.0.0.0:<port>: before, the network's datagrams reached its judge, which stopped as told,
// and so did the same host's. Now the host bus's processes take only datagrams looped back on
// loopback (the network's are dropped) in a network namespace of the worker's own (nothing else
// of the host is in it): the verdicts are the one-host run's.
TEST_F(MultiHostTest, DatagramsSprayedAtAWorkersPortsFromTheNetworkOrItsOwnHostChangeNothing) {
  ASSERT_EQ(mtg(run_args("one", 12, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));
  make_hosts(1);
  start_worker(0);
  const fs::path worker_log = fx_.root() / "worker0.log";
  ASSERT_TRUE(wait_for([&] { return testing_multihost::read_text(worker_log).find(", capacity ") != std::string::npos; },
                       15000)) << log_text();
  EXPECT_NE(testing_multihost::read_text(worker_log).find("in a network namespace of its own"), std::string::npos)
      << testing_multihost::read_text(worker_log);

  bus::Bus tap(kSharedUrl);  // no key: it reads the announcements as they are
  std::string run_id;
  std::set<std::int64_t> granted;
  tap.subscribe_raw(bus::kRunInfo, [&](const std::string&, std::span<const std::uint8_t> b, std::int64_t) {
    mtg::run_info_t m{};
    if (m.decode(b.data(), 0, static_cast<int>(b.size())) >= 0) run_id = m.header.run_id;
  });
  tap.subscribe_raw("MTG_LEASE.*", [&](const std::string&, std::span<const std::uint8_t> b, std::int64_t) {
    mtg::lease_t m{};
    if (m.decode(b.data(), 0, static_cast<int>(b.size())) >= 0) granted.insert(m.header.episode_id);
  });
  const int from_network = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(from_network, 0);
  // A socket of the worker's host: made by a thread in that host's network namespace.
  int from_host = -1;
  std::thread([&] {
    const int ns = ::open(("/run/netns/" + host(0)).c_str(), O_RDONLY | O_CLOEXEC);
    if (ns >= 0 && ::setns(ns, CLONE_NEWNET) == 0) from_host = ::socket(AF_INET, SOCK_DGRAM, 0);
    if (ns >= 0) ::close(ns);
  }).join();
  ASSERT_GE(from_host, 0) << "a socket in " << host(0) << "'s namespace";
  const unsigned char ttl0 = 0;
  ::setsockopt(from_host, IPPROTO_IP, IP_MULTICAST_TTL, &ttl0, sizeof ttl0);  // as the host bus sends
  const auto host_bus = bus::parse_udpm(bus::kDefaultUrl);
  std::map<std::string, long> sent;
  // One LCM datagram (liblcm's small-message form) to every port of `address`.
  auto spray = [&](int tx, const char* address, const std::string& channel, const auto& msg) {
    std::vector<std::uint8_t> packet = {'L', 'C', '0', '2', 0, 0, 0, 1};
    packet.insert(packet.end(), channel.begin(), channel.end());
    packet.push_back(0);
    const std::size_t at = packet.size();
    packet.resize(at + static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(packet.data() + at, 0, msg.getEncodedSize());
    sockaddr_in to{};
    to.sin_family = AF_INET;
    ::inet_pton(AF_INET, address, &to.sin_addr);
    for (int port = 1; port < 65536; ++port) {
      to.sin_port = htons(static_cast<std::uint16_t>(port));
      if (::sendto(tx, packet.data(), packet.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) > 0) {
        ++sent[address];
      }
    }
  };
  auto spray_everywhere = [&](const std::string& channel, const auto& msg) {
    spray(from_network, "10.77.0.1", channel, msg);
    spray(from_host, "127.0.0.1", channel, msg);
    spray(from_host, host_bus->group.c_str(), channel, msg);
  };
  testing::ChildProcess run(run_args("sprayed", 12, 4, 1), log());
  while (run.running()) {
    tap.handle_once(50);
    if (run_id.empty()) continue;
    mtg::run_control_t stop{};
    stop.header.run_id = run_id;
    stop.header.sender = "forger:0";
    stop.header.schema_version = bus::kSchemaVersion;
    stop.command = "shutdown";
    spray_everywhere(bus::kControl, stop);
    for (const std::int64_t id : granted) {
      mtg::episode_result_t fake{};
      fake.header = stop.header;
      fake.header.episode_id = id;
      fake.success = true;
      fake.ip = 100.0;
      fake.stage = "done";
      spray_everywhere(bus::kEpisodeResult, fake);
    }
  }
  ::close(from_network);
  ::close(from_host);
  ASSERT_EQ(run.wait(1000), 0) << log_text();
  for (const char* address : {"10.77.0.1", "127.0.0.1", host_bus->group.c_str()}) {
    EXPECT_GT(sent[address], 65000) << "the spray at " << address << " went out";
  }
  const auto rows = results("sprayed");
  EXPECT_EQ(rows.size(), planned("sprayed"));
  EXPECT_EQ(fingerprints(rows), single);
  for (const auto& r : rows) EXPECT_EQ(r.status, "scored") << r.task_id << ": " << r.detail;
  for (const auto& entry : fs::recursive_directory_iterator(fx_.root() / "worker0")) {
    if (entry.path().extension() != ".log") continue;
    EXPECT_EQ(testing_multihost::read_text(entry.path()).find("forger"), std::string::npos)
        << entry.path() << " heard the forger:\n" << testing_multihost::read_text(entry.path());
  }
}

// A worker that is not root (a Slurm job's) cannot make a network namespace alone: it first
// becomes the owner of a user namespace of its own, at start while it has one thread, and its
// run's processes enter the namespace it made there. Same verdicts as one host.
TEST_F(MultiHostTest, AWorkerThatIsNotRootKeepsItsHostBusInANamespaceToo) {
  ASSERT_EQ(mtg(run_args("one", 12, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));
  make_hosts(1);
  constexpr int kNobody = 65534;
  start_worker(0, 2, {}, kNobody);
  const fs::path worker_log = fx_.root() / "worker0.log";
  ASSERT_TRUE(wait_for([&] { return testing_multihost::read_text(worker_log).find(", capacity ") != std::string::npos; },
                       15000)) << log_text();
  EXPECT_NE(testing_multihost::read_text(worker_log).find("in a network namespace of its own"), std::string::npos)
      << testing_multihost::read_text(worker_log);
  const auto namespace_of = [](const std::string& link) {
    std::error_code ec;
    const fs::path target = fs::read_symlink(link, ec);
    return ec ? std::string() : target.string();
  };
  // While the run lasts: where the worker is, where bus.json says its host bus is, and where
  // each process it started runs.
  testing::ChildProcess run(run_args("unprivileged", 12, 4, 1), log());
  std::string worker_ns, bus_ns;
  std::map<int, std::string> children;  // pid -> its network namespace
  std::set<std::string> shared_sockets;  // "pid socket:[inode]" a child holds of the worker's
  const auto sockets_of = [](const fs::path& proc) {
    std::set<std::string> out;
    std::error_code ec;
    for (const auto& fd : fs::directory_iterator(proc / "fd", ec)) {
      const std::string target = fs::read_symlink(fd.path(), ec).string();
      if (!ec && target.rfind("socket:", 0) == 0) out.insert(target);
    }
    return out;
  };
  nlohmann::json bus;
  while (run.running()) {
    if (bus.is_null()) {
      for (const auto& entry : fs::recursive_directory_iterator(fx_.root() / "worker0")) {
        if (entry.path().filename() == "bus.json") bus = nlohmann::json::parse(testing_multihost::read_text(entry.path()));
      }
    }
    if (!bus.is_null()) {
      const int worker = bus.at("pid").get<int>();
      if (worker_ns.empty()) worker_ns = namespace_of("/proc/" + std::to_string(worker) + "/ns/net");
      if (bus_ns.empty()) bus_ns = namespace_of(bus.at("netns").get<std::string>());
      const std::set<std::string> workers_sockets = sockets_of("/proc/" + std::to_string(worker));
      for (const auto& proc : fs::directory_iterator("/proc")) {
        std::ifstream stat(proc.path() / "stat");
        std::string pid, name, state;
        int parent = 0;
        if (!(stat >> pid >> name >> state >> parent) || parent != worker) continue;
        const std::string ns = namespace_of((proc.path() / "ns/net").string());
        if (!ns.empty()) children[std::stoi(pid)] = ns;
        for (const std::string& socket : sockets_of(proc.path())) {
          if (workers_sockets.count(socket)) shared_sockets.insert(pid + " " + socket);
        }
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_EQ(run.wait(1000), 0) << log_text();
  const auto rows = results("unprivileged");
  EXPECT_EQ(fingerprints(rows), single);
  for (const auto& r : rows) EXPECT_NE(r.worker.find("host0"), std::string::npos) << r.worker;
  ASSERT_FALSE(bus.is_null()) << "the worker wrote its run's bus.json";
  EXPECT_TRUE(bus.at("own_namespace").get<bool>()) << bus.dump();
  EXPECT_TRUE(bus.at("user_namespace").get<bool>()) << bus.dump();
  ASSERT_FALSE(worker_ns.empty());
  ASSERT_FALSE(bus_ns.empty());
  EXPECT_NE(bus_ns, worker_ns) << "the host bus is not in the host's own namespace";
  EXPECT_GE(children.size(), 4u) << "recorder, scene graph, judge and agents seen";
  for (const auto& [pid, ns] : children) EXPECT_EQ(ns, bus_ns) << "process " << pid << " runs outside the host bus's namespace";
  // liblcm's sockets are not close-on-exec: before, every process inherited the worker's
  // shared-bus sockets, a way out of the namespace onto the hosts' network.
  EXPECT_TRUE(shared_sockets.empty()) << *shared_sockets.begin() << " (and " << shared_sockets.size() - 1 << " more)";
}

// A worker whose dataset lacks a file the task set was made from stays out of the run, says why,
// and the coordinator prints it; the other worker runs every episode.
TEST_F(MultiHostTest, AWorkerWithAnotherDatasetStaysOutAndSaysWhy) {
  ASSERT_EQ(mtg(run_args("one", 2, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));
  const fs::path copy = fx_.root() / "other_data";
  fs::create_directories(copy);
  for (const auto& entry : fs::directory_iterator(fx_.root())) {
    const std::string name = entry.path().filename().string();
    if (name == "configs" || name == "objects" || name.find("scene_dataset_config") != std::string::npos) {
      fs::copy(entry.path(), copy / name, fs::copy_options::recursive);
    }
  }
  std::string removed;
  for (const auto& f : fs::recursive_directory_iterator(copy / "objects")) {
    if (f.path().filename().string().rfind("box", 0) == 0) removed = f.path().string();
  }
  ASSERT_FALSE(removed.empty());
  fs::remove(removed);
  make_hosts(2);
  start_worker(0);
  start_worker(1, 2, {"--data", copy.string()});
  // Both workers listen before the run starts (a worker logs its first line once subscribed):
  // the run's fingerprints come in one announcement of five, one a second, and this run is over
  // in well under a second, so a worker still starting would never hear them.
  for (const int i : {0, 1}) {
    const fs::path log = fx_.root() / ("worker" + std::to_string(i) + ".log");
    const auto listening = [&] { return testing_multihost::read_text(log).find(", capacity ") != std::string::npos; };
    ASSERT_TRUE(wait_for(listening, 15000)) << log_text();
  }
  auto args = run_args("mixed", 2, 4, 1);
  ASSERT_EQ(mtg(args), 0) << log_text();
  const auto rows = results("mixed");
  EXPECT_EQ(fingerprints(rows), single);
  for (const auto& r : rows) EXPECT_NE(r.worker.find("host0"), std::string::npos) << r.worker;
  // Host 1 says why once it has checked the run's files, which may be after a short run ends.
  EXPECT_TRUE(wait_for([&] { return log_text().find("is missing here") != std::string::npos; }, 15000)) << log_text();
}

TEST_F(MultiHostTest, AKilledHostsEpisodesRunElsewhereNothingLostNothingTwice) {
  ASSERT_EQ(mtg(run_args("one", 8, 6, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));

  make_hosts(3);
  start_worker(0);
  ::setenv("MTG_FAULTS", "hold_results:1", 1);  // host 1 never delivers: its leases stay held
  start_worker(1);
  ::unsetenv("MTG_FAULTS");
  start_worker(2);
  const pid_t victim = workers_.at(1)->pid();
  testing::ChildProcess run(run_args("killed", 8, 6, 3), log());
  const std::string suffix = ":" + std::to_string(victim);
  auto victim_leases = [&] {
    int held = 0;
    for (const auto& [worker, n] : open_leases("killed")) {
      if (worker.size() > suffix.size() && worker.compare(worker.size() - suffix.size(), suffix.size(), suffix) == 0) {
        held += n;
      }
    }
    return held;
  };
  // Kill host 1 mid-run, while it holds leases (it cannot finish them: it delivers nothing).
  ASSERT_TRUE(wait_for([&] { return results("killed").size() >= 2 && victim_leases() > 0; }, 60000)) << log_text();
  kill_host(1);
  EXPECT_EQ(workers_.count(1), 0u);
  ASSERT_EQ(run.wait(180000), 0) << log_text();
  EXPECT_NE(log_text().find("not renewed"), std::string::npos) << log_text();

  const auto rows = results("killed");
  EXPECT_EQ(rows.size(), planned("killed"));
  EXPECT_EQ(fingerprints(rows), single);
  int retried = 0;
  for (const auto& r : rows) retried += r.attempt > 0 ? 1 : 0;
  EXPECT_GT(retried, 0) << "the dead host's leases were re-issued";
  expect_one_start_per_episode("killed");
}

TEST_F(MultiHostTest, AKilledCoordinatorRestartedAdoptsTheLeasesStillOut) {
  ASSERT_EQ(mtg(run_args("one", 8, 4, 0)), 0) << log_text();
  const auto single = fingerprints(results("one"));

  make_hosts(2);
  for (int i = 0; i < 2; ++i) start_worker(i);
  const auto args = run_args("restart", 8, 4, 2);
  {
    testing::ChildProcess run(args, log());
    // The book is read with the coordinator stopped, so the kill lands on the state that was read:
    // a running coordinator may close its last open lease between the read and the kill.
    ASSERT_TRUE(wait_for([&] {
      ::kill(run.pid(), SIGSTOP);
      bool ready = false;
      try {
        int out = 0;
        for (const auto& [worker, n] : open_leases("restart")) out += n;
        ready = out > 0 && results("restart").size() >= 3;
      } catch (...) {
        ::kill(run.pid(), SIGCONT);  // its databases are still being made
        throw;
      }
      if (!ready) ::kill(run.pid(), SIGCONT);
      return ready;
    }, 60000)) << log_text();
    run.kill(SIGKILL);
  }
  const auto before = results("restart");
  ASSERT_LT(before.size(), planned("restart"));
  int out_at_kill = 0;
  for (const auto& [worker, n] : open_leases("restart")) out_at_kill += n;
  ASSERT_GT(out_at_kill, 0);
  // A lease is closed in the book before its release is sent, so a coordinator killed between the
  // two leaves a worker holding a lease the book calls done. Any lease a worker holds must be in
  // the book, out or done; none may be one the coordinator never wrote down.
  int done_at_kill = 0;
  for (const auto& [worker, n] : leases_in_state("restart", orchestrator::remote::LeaseState::kDone)) done_at_kill += n;

  // Meanwhile the workers hold their leases (finished ones wait for a release): mtg status.
  const std::string status_file = (fx_.root() / "status.json").string();
  {
    testing::ChildProcess status({testing::bin("mtg"), "status", "--bus", kSharedUrl, "--json"}, status_file);
    ASSERT_EQ(status.wait(30000), 0) << log_text();
  }
  std::ifstream in(status_file);
  const auto status = nlohmann::json::parse(in);
  ASSERT_EQ(status["workers"].size(), 2u) << status.dump();
  int held = 0;
  for (const auto& w : status["workers"]) {
    EXPECT_EQ(w["run"].get<std::string>().rfind("restart-", 0), 0u) << w["run"];
    held += w["in_flight"].get<int>();
  }
  EXPECT_GE(held, 1);
  EXPECT_LE(held, out_at_kill + done_at_kill);

  ASSERT_EQ(mtg(args), 0) << log_text();
  const auto rows = results("restart");
  EXPECT_EQ(rows.size(), planned("restart"));
  EXPECT_EQ(fingerprints(rows), single);
  expect_one_start_per_episode("restart");
  EXPECT_NE(log_text().find("adopting"), std::string::npos) << log_text();
}

TEST_F(MultiHostTest, ImagesCrossHostsOnlyInVerifiedRecordingsEvenWhenChunksAreLost) {
  make_hosts(2);
  ::setenv("MTG_FAULTS", "drop_chunk:5", 1);  // every 5th chunk lost on the first sending
  for (int i = 0; i < 2; ++i) start_worker(i, 2, {"--chunk-bytes", "16384"});
  ::unsetenv("MTG_FAULTS");
  auto args = run_args("images", 1, 4, 2);
  args.push_back("--render");
  args.push_back("--image-size");
  args.push_back("160x120");
  ASSERT_EQ(mtg(args), 0) << log_text();
  const auto rows = results("images");
  ASSERT_EQ(rows.size(), planned("images"));
  std::set<std::string> used;
  for (const auto& r : rows) used.insert(r.worker);
  EXPECT_EQ(used.size(), 2u);
  expect_one_start_per_episode("images");
  // Every observation of every stored attempt is in the merged recording with its images, and
  // each episode's observations are numbered 0, 1, 2, ... without a gap.
  std::map<std::int64_t, std::vector<std::int64_t>> seqs;
  int observations = 0, with_images = 0;
  bus::for_each_recorded_event(fx_.root() / "images", [&](const lcm::LogEvent& ev) {
    if (!bus::is_episode_channel(ev.channel, bus::EpisodeStream::kObservation)) return;
    mtg::observation_t m{};
    ASSERT_GE(m.decode(ev.data, 0, ev.datalen), 0);
    if (!m.done) {  // the closing observation (the episode is over) has nothing to look at
      ++observations;
      with_images += m.n_images > 0 ? 1 : 0;
    }
    seqs[m.header.episode_id].push_back(m.header.seq);
  });
  EXPECT_GT(observations, static_cast<int>(rows.size()));
  EXPECT_EQ(with_images, observations);
  for (const auto& [id, s] : seqs) {
    for (std::size_t i = 0; i < s.size(); ++i) EXPECT_EQ(s[i], static_cast<std::int64_t>(i)) << "episode " << id;
  }
  for (const auto& r : rows) {
    if (r.agent == "oracle") {
      EXPECT_TRUE(r.success) << r.task_id;
    }
  }
  std::uintmax_t largest = 0;
  for (const auto& f : fs::directory_iterator(fx_.root() / "images" / "episodes")) {
    largest = std::max(largest, fs::file_size(f.path()));
  }
  EXPECT_GT(largest, 5u * 16384u) << "a recording of more than 5 chunks: one was lost and resent";
}

TEST_F(MultiHostTest, ModelAgentsOnTwoHostsShareTheCoordinatorsRateGovernor) {
  make_hosts(2);
  // The model server listens on the bridge, where both hosts reach it; it answers 429 beyond
  // 8 requests per 2 s, and the run is told the same limit.
  testing::FakeModelServer server("10.77.0.254");
  std::map<std::string, std::vector<std::string>> plans;
  for (const auto& t : tasks::read_tasks(tasks_db_)) plans.emplace(t.text, t.oracle);
  server.set_model(testing::oracle_model(plans));
  server.enforce_limit(8, std::chrono::milliseconds(2000));
  for (int i = 0; i < 2; ++i) start_worker(i);
  const std::string spec = "openai-compatible:http://10.77.0.254:" + std::to_string(server.port()) + "/v1:oracle";
  const std::vector<std::string> args = {
      testing::bin("mtg"), "run", "--tasks", tasks_db_, "--levels", "1,3", "--limit", "2", "--parallel", "4", "--out",
      (fx_.root() / "model").string(), "--data", fx_.root().string(), "--profile", "none", "--no-progress",
      "--agent", spec, "--image-size", "160x120", "--no-cache", "--rpm", "8", "--rate-window", "2", "--remote",
      "--bus", kSharedUrl, "--min-workers", "2"};
  ASSERT_EQ(mtg(args), 0) << log_text();
  const auto rows = results("model");
  ASSERT_EQ(rows.size(), planned("model"));
  std::set<std::string> used;
  for (const auto& r : rows) {
    EXPECT_TRUE(r.success) << r.task_id << ": " << r.detail;
    EXPECT_GT(r.usage.images_sent, 0);
    used.insert(r.worker);
  }
  EXPECT_EQ(used.size(), 2u);
  const auto seen = server.requests();
  EXPECT_EQ(server.answered_429(), 0) << "the governor let too many through";
  int busiest = 0;
  for (const auto& a : seen) {
    int n = 0;
    for (const auto& b : seen) n += b.at_ms >= a.at_ms && b.at_ms < a.at_ms + 2000.0 ? 1 : 0;
    busiest = std::max(busiest, n);
  }
  EXPECT_LE(busiest, 8);
  EXPECT_GE(seen.size(), 16u);
}

// Bad input and missing peers: one line on stderr naming what is wrong, exit 1, no hang.
TEST(MultiHostErrors, NoWorkersNoOneOnTheBusAndAWorkerWithoutABusFailWithOneLine) {
  testing::FixtureDataset fx;
  const std::string db = testing::two_tables_task_db(fx);
  auto run = [&](const std::vector<std::string>& args) {
    const std::string log = (fx.root() / "out.log").string();
    testing::ChildProcess p(args, log);
    const int status = p.wait(60000);
    std::ifstream in(log);
    return std::make_pair(status, std::string(std::istreambuf_iterator<char>(in), {}));
  };
  const std::string url = "udpm://239.255.76.67:7667?ttl=0";  // this test's own loopback bus
  const std::string key = (fx.root() / "bus.key").string();
  std::ofstream(key) << "test-secret-of-the-errors-test\n";

  ::unsetenv("MTG_BUS_KEY");
  const auto [no_key, key_why] = run({testing::bin("mtg"), "run", "--tasks", db, "--agent", "oracle", "--out",
                                      (fx.root() / "nokey").string(), "--data", fx.root().string(), "--profile",
                                      "none", "--remote", "--bus", url, "--worker-wait", "1", "--no-progress"});
  EXPECT_EQ(no_key, 1);
  EXPECT_NE(key_why.find("needs a key: --bus-key FILE"), std::string::npos) << key_why;

  const auto [no_workers, why] = run({testing::bin("mtg"), "run", "--tasks", db, "--agent", "oracle", "--out",
                                      (fx.root() / "r").string(), "--data", fx.root().string(), "--profile", "none",
                                      "--remote", "--bus", url, "--bus-key", key, "--worker-wait", "1",
                                      "--no-progress"});
  EXPECT_EQ(no_workers, 1);
  EXPECT_NE(why.find("only 0 of 1 workers joined in 1 s"), std::string::npos) << why;
  EXPECT_NE(why.find("mtg worker --bus"), std::string::npos) << why;

  const auto [nobody, said] = run({testing::bin("mtg"), "status", "--bus", url, "--listen", "0.5"});
  EXPECT_EQ(nobody, 1);
  EXPECT_NE(said.find("nothing heard on udpm://239.255.76.67:7667"), std::string::npos) << said;

  const auto [same_bus, told] = run({testing::bin("mtg"), "worker", "--bus", url, "--local-url", url});
  EXPECT_EQ(same_bus, 1);
  EXPECT_NE(told.find("must differ from the shared bus"), std::string::npos) << told;

  const auto [bad_url, error] =
      run({testing::bin("mtg"), "worker", "--bus", "udpm://not-an-address:1?ttl=1", "--bus-key", key});
  EXPECT_EQ(bad_url, 1);
  EXPECT_NE(error.find("not-an-address"), std::string::npos) << error;
}

}  // namespace
}  // namespace mtg
