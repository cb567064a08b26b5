// Every message type survives publish -> receive unchanged, on a real udpm bus (in this test's
// own network namespace) and on memq.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <optional>

#include "bus/bus.h"
#include "bus/convert.h"
#include "bus/header.h"
#include "bus/observation_packing.h"
#include "bus/recording.h"
#include "bus/channels.h"
#include "bus/truth_seal.h"
#include "bus/url.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_result_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"
#include "mtg/error_event_t.hpp"
#include "mtg/heartbeat_t.hpp"
#include "mtg/judge_event_t.hpp"
#include "mtg/lease_renewal_t.hpp"
#include "mtg/lease_t.hpp"
#include "mtg/recording_ref_t.hpp"
#include "mtg/recording_request_t.hpp"
#include "bus/recording_ref.h"
#include "mtg/observation_t.hpp"
#include "mtg/render_request_t.hpp"
#include "mtg/render_result_t.hpp"
#include "mtg/run_control_t.hpp"
#include "mtg/scene_request_t.hpp"
#include "mtg/scene_summary_t.hpp"
#include "mtg/state_update_t.hpp"
#include "mtg/task_set_request_t.hpp"
#include "mtg/task_set_summary_t.hpp"
#include "tests/support/graph_fixtures.h"
#include "tests/support/same_world_state.h"

namespace mtg::bus {
namespace {

template <class Msg>
std::vector<std::uint8_t> encode(const Msg& m) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_GT(m.encode(buf.data(), 0, static_cast<int>(buf.size())), 0);
  return buf;
}

mtg::image_t sample_image(int nbytes) {
  mtg::image_t im{};
  im.role = "view_marked";
  im.caption = "The close-up Z1 (framed here) shows small or crowded objects larger.";
  im.encoding = "png";
  im.width = 640;
  im.height = 480;
  im.content_hash = "0123456789abcdef";
  im.nbytes = nbytes;
  im.data.resize(static_cast<std::size_t>(nbytes));
  for (int i = 0; i < nbytes; ++i) im.data[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i * 7);
  return im;
}

mtg::task_t sample_task() {
  mtg::task_t t{};
  t.task_id = "apt_0/L1/000001";
  t.scene = "apt_0";
  t.level = 1;
  t.task_type = "surface_part";
  t.text = "Move the cup to the front part of the table.";
  return t;
}

class RoundTrip {
 public:
  explicit RoundTrip(const std::string& url) : bus_(url), stamp_("run-1", "test:0") {}

  template <class Msg>
  void check(const std::string& channel, Msg msg) {
    msg.header = stamp_.next(bus::EpisodeId(7), 1);
    std::optional<Msg> got;
    bus_.subscribe<Msg>(channel, [&got](const std::string&, const Msg& m) { got = m; });
    bus_.publish(channel, msg);
    ASSERT_TRUE(bus_.handle_until([&] { return got.has_value(); }, 3000)) << channel;
    EXPECT_EQ(encode(*got), encode(msg)) << channel;
  }

  void check_all() {
    mtg::scene_request_t scene_req{};
    scene_req.request_id = "r1";
    scene_req.scene = "apt_0";
    scene_req.want = "info";
    check("T_SCENE_REQ", scene_req);

    mtg::scene_summary_t summary{};
    summary.ok = true;
    summary.scene = "apt_0";
    summary.objects = 119;
    summary.triangles = 1234567;
    summary.details_json = R"({"scene":"apt_0"})";
    check("T_SCENE_SUMMARY", summary);

    mtg::task_set_request_t ts_req{};
    ts_req.scene = "apt_0";
    ts_req.levels = "1,2,3,4";
    ts_req.seed = 42;
    check("T_TASKSET_REQ", ts_req);

    mtg::task_set_summary_t ts{};
    ts.ok = true;
    ts.level_counts[0] = 10;
    ts.level_counts[3] = 4;
    ts.total = 14;
    check("T_TASKSET_SUMMARY", ts);

    mtg::episode_truth_t truth{};
    truth.task_id = "apt_0/L1/000001";
    truth.goal_json = R"({"atomic":{"item":"cup_01_3"}})";
    truth.n_oracle = 3;
    truth.oracle_plan = {"l4", "o2", "startplace"};
    truth.identify_json = "[]";
    check("T_TRUTH", truth);

    mtg::episode_start_t start{};
    start.task = sample_task();
    start.agent = "oracle";
    start.seed = -5;
    start.step_limit = 15;
    start.render = true;
    check("T_EPISODE_START", start);

    mtg::observation_t obs{};
    obs.step = 3;
    obs.step_limit = 15;
    obs.task_text = "Move the cup.";
    obs.text = "You stand at table_01_48_platform_0.";
    obs.n_actions = 2;
    obs.actions.resize(2);
    obs.actions[0].key = "l1";
    obs.actions[0].description = "go to platform 1";
    obs.actions[1].key = "0";
    obs.actions[1].description = "call_end";
    obs.n_images = 1;
    obs.images = {sample_image(1000)};
    check("T_OBS", obs);

    mtg::render_request_t rreq{};
    rreq.request_id = 9;
    rreq.n_views = 1;
    rreq.views.resize(1);
    rreq.views[0].view = "platform";
    rreq.views[0].side = 2;
    rreq.views[0].number = 7;
    rreq.views[0].caption = "The object the task calls 'the leftmost book', object 7 here";
    rreq.width = 640;
    rreq.height = 480;
    rreq.state.phase = mtg::world_state_delta_t::PHASE_PLACING;
    rreq.state.held = "cup_1";
    rreq.state.n_moved = 1;
    rreq.state.moved.resize(1);
    rreq.state.moved[0].object = "cup_1";
    rreq.state.moved[0].position[2] = 0.75;
    rreq.state.moved[0].n_vertices = 2;
    rreq.state.moved[0].footprint_x = {0.1 / 3, 0.2};
    rreq.state.moved[0].footprint_y = {-0.2 / 7, 0.3};
    rreq.state.n_reordered = 1;
    rreq.state.reordered = {{"table_1", 2, {"cup_2", "cup_3"}}};
    rreq.with_observation = true;
    rreq.observation = obs;
    rreq.observation.images.clear();
    rreq.observation.n_images = 0;
    check("T_RENDER_REQ", rreq);

    mtg::render_result_t rres{};
    rres.request_id = 9;
    rres.ok = true;
    rres.images_published = 3;
    rres.n_images = 2;
    rres.images = {sample_image(10), sample_image(20)};
    check("T_RENDER_RES", rres);

    mtg::agent_action_t act{};
    act.step = 3;
    act.raw_reply = "Action: l12";
    act.parsed_key = "l12";
    act.format_ok = true;
    act.cost_usd = 0.0125;
    check("T_ACT", act);

    mtg::state_update_t state{};
    state.step = 5;
    state.key = "5";
    state.side = 1;
    state.applied = true;
    state.hint = "placed";
    state.n_moved = 1;
    state.moved.resize(1);
    state.moved[0].object = "cup_01_3";
    state.moved[0].platform = "rack_01_76_platform_2";
    state.moved[0].n_vertices = 3;
    state.moved[0].footprint_x = {0.0, 1.0, 0.0};
    state.moved[0].footprint_y = {0.0, 0.0, 1.0};
    check("T_STATE", state);

    mtg::judge_event_t judge{};
    judge.kind = "milestone";
    judge.milestone = 2;
    judge.ip = 50.0;
    check("T_JUDGE", judge);

    mtg::episode_result_t result{};
    result.task_id = "apt_0/L3/000002";
    result.level = 3;
    result.ip = 62.5;
    result.stage = "picked";
    result.cause = "wrong_region";
    result.n_subtasks = 2;
    result.subtask_ip = {100.0, 25.0};
    result.subtask_success = {true, false};
    check("T_RESULT", result);

    mtg::heartbeat_t hb{};
    hb.role = "worker";
    hb.capacity = 4;
    hb.tick = 99;
    check("T_HEARTBEAT", hb);

    mtg::lease_t lease{};
    lease.lease_id = "L1";
    lease.action = "grant";
    lease.ttl_ms = 5000;
    check("T_LEASE", lease);

    mtg::lease_renewal_t renewal{};
    renewal.worker = "worker:host1:42";
    renewal.episode_ids = {7, 9};
    renewal.attempts = {0, 3};
    renewal.n_leases = 2;
    check("T_RENEWAL", renewal);

    mtg::recording_ref_t ref{};
    ref.location = "/shared/recordings/run/E7-a0.lcmlog";
    ref.host = "host1";
    ref.shared = true;
    ref.bytes = 1700000;
    ref.sha256 = bus::sha256_hex(std::vector<std::uint8_t>{1, 2, 3});
    check("T_RECORD_REF", ref);

    mtg::recording_request_t wanted{};
    wanted.host = "host1";
    wanted.locations = {"/w/run/episodes/E7-a0.lcmlog"};
    wanted.episode_ids = {7};
    wanted.attempts = {0};
    wanted.n_files = 1;
    check("T_RECORD_REQ", wanted);

    mtg::run_control_t control{};
    control.command = "shutdown";
    check("T_CONTROL", control);

    mtg::error_event_t error{};
    error.severity = "warning";
    error.message = "render request: unknown platform 'x'";
    check("T_ERROR", error);
  }

  Bus& bus() { return bus_; }

 private:
  Bus bus_;
  HeaderStamper stamp_;
};

TEST(BusRoundTrip, EveryTypeOverUdpm) {
  RoundTrip rt(kDefaultUrl);
  rt.check_all();
}

TEST(BusRoundTrip, EveryTypeOverMemq) {
  RoundTrip rt("memq://");
  rt.check_all();
}

// The answers sealed on one bus open on another with the same key, bound to their episode; a
// bus with another key, or one fed answers in clear, drops them and counts them.
TEST(BusRoundTrip, SealedAnswersOpenOnlyWithTheRunsKeyAndOnlyForTheirEpisode) {
  const auto key = std::make_shared<const TruthSeal>(TruthSeal::derived("a secret of at least 16 bytes", "run-7"));
  mtg::episode_truth_t truth{};
  truth.header = HeaderStamper("run-7", "test").next(EpisodeId(4), 1, "truth");
  truth.task_id = "apt_0/L1/000001";
  truth.goal_json = R"({"atomic":{"item":"box_1"}})";
  truth.oracle_plan = {"l3", "o1", "l5", "startplace", "2", "0"};
  truth.n_oracle = 6;
  truth.identify_json = "[]";
  const auto sealed = key->seal(truth);
  EXPECT_TRUE(is_sealed(sealed));
  EXPECT_TRUE(sealed.goal_json.empty() && sealed.oracle_plan.empty() && sealed.identify_json.empty());
  const std::string bytes(sealed.sealed.begin(), sealed.sealed.end());
  EXPECT_EQ(bytes.find("box_1"), std::string::npos);
  const auto opened = TruthSeal::derived("a secret of at least 16 bytes", "run-7").open(sealed);
  EXPECT_EQ(opened.goal_json, truth.goal_json);
  EXPECT_EQ(opened.oracle_plan, truth.oracle_plan);
  EXPECT_EQ(opened.identify_json, truth.identify_json);
  EXPECT_THROW(TruthSeal::derived("a secret of at least 16 bytes", "run-8").open(sealed), Error);
  auto other_attempt = sealed;
  other_attempt.header.attempt = 2;
  EXPECT_THROW(key->open(other_attempt), Error);
  auto flipped = sealed;
  flipped.sealed[20] ^= 1;
  EXPECT_THROW(key->open(flipped), Error);

  // Over a bus: sealed by the publisher's bus, opened by a subscriber's with the key; one with
  // another key gets nothing, one without a key gets them sealed; answers in clear (a process
  // without the key posing as the orchestrator) are refused by a keyed bus.
  Bus publisher(kDefaultUrl), same(kDefaultUrl), other(kDefaultUrl), none(kDefaultUrl);
  publisher.seal_truths(key);
  same.seal_truths(key);
  other.seal_truths(std::make_shared<const TruthSeal>(TruthSeal::random()));
  std::vector<mtg::episode_truth_t> at_same, at_other, at_none;
  auto into = [](std::vector<mtg::episode_truth_t>& v) {
    return [&v](const std::string&, const mtg::episode_truth_t& m) { v.push_back(m); };
  };
  same.subscribe<mtg::episode_truth_t>(kEpisodeTruth, into(at_same));
  other.subscribe<mtg::episode_truth_t>(kEpisodeTruth, into(at_other));
  none.subscribe<mtg::episode_truth_t>(kEpisodeTruth, into(at_none));
  publisher.publish(kEpisodeTruth, truth);
  none.publish(kEpisodeTruth, truth);  // in clear
  auto pump = [&] {
    for (int i = 0; i < 40 && (at_none.size() < 2 || same.unopened() + other.unopened() < 3); ++i) {
      for (Bus* b : {&same, &other, &none}) b->handle_once(10);
    }
  };
  pump();
  ASSERT_EQ(at_same.size(), 1u);
  EXPECT_EQ(at_same[0].goal_json, truth.goal_json);
  EXPECT_EQ(same.unopened(), 1) << "the answers in clear";
  EXPECT_TRUE(at_other.empty());
  EXPECT_EQ(other.unopened(), 2);
  ASSERT_EQ(at_none.size(), 2u);
  EXPECT_EQ(at_none[0].goal_json.empty() + at_none[1].goal_json.empty(), 1) << "one sealed, one in clear";
}

TEST(BusRoundTrip, OneMegabyteImageOverUdpm) {
  RoundTrip rt(kDefaultUrl);
  mtg::render_result_t big{};
  big.ok = true;
  big.n_images = 1;
  big.images = {sample_image(1 << 20)};
  rt.check("T_BIG", big);
}

// The renderer rebuilds the scene-graph service's world state from the request: through the
// message's bytes, every double must come back bit for bit.
TEST(BusRoundTrip, AWorldStateCrossesTheBusBitForBit) {
  testing::FixtureDataset fx;
  const auto built = testing::two_tables(fx);
  const graph::SceneGraph& g = built.graph;
  episode::WorldState s = episode::initial_state(g);
  const graph::PlatformId from = g.platforms[g.navigable[0]].items.empty() ? g.navigable[1] : g.navigable[0];
  s.phase = episode::Phase::kAtPlatform;
  s.at_platform = from;
  s.side = 1;
  s.steps = 4;
  episode::pick(g, s, g.platforms[from].items.front());
  const graph::PlatformId other = g.navigable.back();
  episode::place_held(g, s, other, episode::platform_frame(g, s, other).translation() + Eigen::Vector2d(0.1 / 3, -0.2 / 7));
  s.platform_offset[g.navigable[0]] = Eigen::Vector3d(0.1 / 3, -0.0, 1e-17);  // carried along

  const mtg::world_state_delta_t sent = to_message(episode::state_delta(g, s));
  ASSERT_EQ(sent.n_moved, 1);
  ASSERT_EQ(sent.n_offsets, 1);
  EXPECT_GE(sent.moved[0].placed_side, 0);
  std::vector<std::uint8_t> bytes = encode(sent);
  mtg::world_state_delta_t received{};
  ASSERT_EQ(received.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  const episode::WorldState back = episode::apply_delta(g, from_message(received));
  testing::expect_same_world_state(back, s);
}

TEST(BusHeader, SequenceTrackerFlagsGapsAndDuplicates) {
  HeaderStamper stamp("run", "sg:0");
  SequenceTracker tracker;
  const auto h0 = stamp.next(bus::EpisodeId(1), 0);
  const auto h1 = stamp.next(bus::EpisodeId(1), 0);
  const auto h2 = stamp.next(bus::EpisodeId(1), 0);
  const auto h3 = stamp.next(bus::EpisodeId(1), 0);
  EXPECT_EQ(tracker.observe(h0), SequenceTracker::Verdict::kInOrder);
  EXPECT_EQ(tracker.observe(h1), SequenceTracker::Verdict::kInOrder);
  EXPECT_EQ(tracker.observe(h1), SequenceTracker::Verdict::kDuplicate);
  EXPECT_EQ(tracker.observe(h3), SequenceTracker::Verdict::kGap);  // h2 lost
  EXPECT_EQ(tracker.observe(h2), SequenceTracker::Verdict::kDuplicate);
  // Another episode, another stream.
  EXPECT_EQ(tracker.observe(stamp.next(bus::EpisodeId(2), 0)), SequenceTracker::Verdict::kInOrder);
}

// A judge serving several runs finishes episode 1 of one run: the other run's episode 1, from
// the same sender, goes on in sequence rather than reading as a gap.
TEST(BusHeader, SequenceTrackerForgetsOneRunsEpisodeOnly) {
  HeaderStamper a("run-a", "sg:0"), b("run-b", "sg:0");
  SequenceTracker tracker;
  EXPECT_EQ(tracker.observe(a.next(bus::EpisodeId(1), 0)), SequenceTracker::Verdict::kInOrder);
  EXPECT_EQ(tracker.observe(b.next(bus::EpisodeId(1), 0)), SequenceTracker::Verdict::kInOrder);
  tracker.forget_episode("run-a", EpisodeId(1));
  EXPECT_EQ(tracker.observe(b.next(bus::EpisodeId(1), 0)), SequenceTracker::Verdict::kInOrder);
  EXPECT_EQ(tracker.observe(a.next(bus::EpisodeId(1), 1)), SequenceTracker::Verdict::kInOrder);  // a new attempt, from 0
}

// A process of another mtg version on the same bus: its typed messages may decode and mean
// something else, so they are dropped and counted; and a recording of another schema is refused
// with one line rather than read wrongly.
TEST(BusHeader, AnotherSchemaVersionIsDroppedLiveAndRefusedInARecording) {
  Bus bus("memq://");
  std::vector<std::int64_t> got;
  bus.subscribe<mtg::heartbeat_t>("T_HB", [&](const std::string&, const mtg::heartbeat_t& m) { got.push_back(m.tick); });
  HeaderStamper stamp("run", "other:0");
  mtg::heartbeat_t hb{};
  hb.header = stamp.next();
  hb.tick = 1;
  bus.publish("T_HB", hb);
  hb.header.schema_version = kSchemaVersion + 1;
  hb.tick = 2;
  bus.publish("T_HB", hb);
  while (bus.handle_once(0)) {
  }
  EXPECT_EQ(got, std::vector<std::int64_t>{1});
  EXPECT_EQ(bus.foreign_schema(), 1);

  const auto dir = std::filesystem::temp_directory_path() / ("mtg-schema-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    lcm::LogFile log((dir / "bus.lcmlog").string(), "w");
    const std::vector<std::uint8_t> bytes = encode(hb);
    lcm::LogEvent ev{};
    ev.eventnum = 0;
    ev.timestamp = 0;
    ev.channel = "MTG_HEARTBEAT";
    ev.datalen = static_cast<int32_t>(bytes.size());
    ev.data = const_cast<std::uint8_t*>(bytes.data());
    ASSERT_EQ(log.writeEvent(&ev), 0);
  }
  try {
    for_each_recorded_event(dir, [](const lcm::LogEvent&) { ADD_FAILURE() << "an event of another schema was read"; });
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("schema version " + std::to_string(kSchemaVersion + 1)), std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(dir);
}


// Schema 7: observations travel packed (bus/observation_packing.h). What a reader makes of them
// is, field for field, what the scene graph and the renderer made; a step that repeats the
// previous one costs a small fraction of it; what a reader cannot have is an error, never other words.
mtg::observation_t step_observation(int step, bool holding) {
  mtg::observation_t o{};
  o.header.run_id = "pack";
  o.header.episode_id = 3;
  o.header.attempt = 1;
  o.step = step;
  o.step_limit = 15;
  o.task_text = "Put the clock from cabinet_5_platform_1 on the center part of bin_03_4_platform_0.";
  o.text = "You are standing at the rear side of platform bin_02_3_platform_0 (l2). " +
           std::string(holding ? "You hold an object." : "Your hand is empty.") + " You have used " +
           std::to_string(step) + " of 15 steps.";
  o.hint = step == 2 ? "That platform has no free part left." : "";
  o.actions.push_back({"0", "call_end: finish the task now"});
  if (holding) o.actions.push_back({"startplace", "start placing the object in your hand on this platform"});
  for (int i = 1; i <= 60; ++i) {
    o.actions.push_back({"l" + std::to_string(i), "go to platform " + std::to_string(i) + ": wall_cabinet_0" +
                                                     std::to_string(i % 7) + "_platform_" + std::to_string(i % 5)});
  }
  o.n_actions = static_cast<int32_t>(o.actions.size());
  return o;
}

mtg::observation_t through_the_bus(const mtg::observation_t& o) {
  const auto bytes = encode(o);
  mtg::observation_t back{};
  EXPECT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return back;
}

TEST(ObservationPacking, AReaderGetsEveryObservationAsItWasMadeAndARepeatedStepIsSmall) {
  WordsCodec codec;
  WordsPacker packer;
  ObservationReader reader;
  std::vector<mtg::observation_t> sent;
  auto made_at = [](int step) {
    // Steps 3 and 4 hold an object (an option added in the middle of the list), step 5 places
    // it (another list), step 6 is back to the first list, step 7 ends the attempt.
    mtg::observation_t m = step_observation(step, step == 3 || step == 4);
    if (step == 5) {
      m.actions.clear();
      for (int cell = 1; cell <= 9; ++cell) {
        m.actions.push_back({std::to_string(cell), "place it in part " + std::to_string(cell) + " of the platform"});
      }
      m.n_actions = 9;
    }
    m.done = step == 7;
    if (m.done) {
      m.actions.clear();
      m.n_actions = 0;
    }
    return m;
  };
  for (int step = 0; step <= 7; ++step) {
    mtg::observation_t made = made_at(step);
    mtg::observation_t packed = made;
    packer.pack(packed, codec);
    EXPECT_TRUE(packed.packed);
    EXPECT_EQ(packed.packed_base, step - 1);
    // An unchanged list of 61 actions and task text: only what changed costs. The first step's
    // long list is compressed.
    if (step == 1 || step == 4 || step == 6) {
      EXPECT_LT(encode(packed).size() * 8, encode(made).size()) << "step " << step;
    }
    if (step == 0) {
      EXPECT_GT(packed.n_zactions, 0);
      EXPECT_LT(encode(packed).size() * 3, encode(made).size()) << "the first step";
    }
    const mtg::observation_t got = reader.whole(through_the_bus(packed), codec);
    EXPECT_EQ(encode(got), encode(made)) << "step " << step;
    // A second copy of a step (a resent observation) reads as the first.
    if (step == 2 || step == 5) {
      EXPECT_EQ(encode(reader.whole(through_the_bus(packed), codec)), encode(made)) << "step " << step;
    }
    sent.push_back(packed);
  }

  // A reader that missed step 1 cannot read step 2, and says which step it lacks.
  ObservationReader missed;
  missed.whole(sent[0], codec);
  try {
    missed.whole(sent[2], codec);
    ADD_FAILURE() << "read step 2 without step 1";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("changes the words of step 1, but step 0 came before it"), std::string::npos)
        << e.what();
  }
  // A damaged compressed list is an error (its frame's checksum), never other actions; so is a
  // run outside what was offered.
  ObservationReader damaged;
  mtg::observation_t first = sent[0];
  first.zactions[first.zactions.size() / 2] ^= 0x5a;
  EXPECT_THROW(damaged.whole(first, codec), Error);
  ObservationReader outside;
  outside.whole(sent[0], codec);
  mtg::observation_t wild = sent[1];
  wild.runs[0] = 30000;
  EXPECT_THROW(outside.whole(wild, codec), Error);
}

// A packed observation of a few kilobytes asked for gigabytes: runs of 32,767 options each, and
// text copies of 32,767 bytes each. Now what it would make is counted first and refused with a
// line naming the step; so is an image whose bytes are not its content hash's.
TEST(ObservationPacking, AnObservationThatWouldGrowPastItsLimitsIsRefusedBeforeItGrows) {
  WordsCodec codec;
  WordsPacker packer;
  std::vector<mtg::observation_t> sent;
  for (int step = 0; step < 2; ++step) {
    mtg::observation_t o = step_observation(step, false);
    packer.pack(o, codec);
    sent.push_back(through_the_bus(o));
  }
  auto refused = [&](mtg::observation_t second, const std::string& why) {
    ObservationReader reader;
    reader.whole(sent[0], codec);
    try {
      reader.whole(std::move(second), codec);
      ADD_FAILURE() << "read: " << why;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("step 1"), std::string::npos) << e.what();
    }
  };
  mtg::observation_t runs = sent[1];
  runs.runs.clear();
  for (int i = 0; i < 700; ++i) runs.runs.insert(runs.runs.end(), {0, 32767});
  runs.n_runs = static_cast<int32_t>(runs.runs.size());
  refused(runs, "offer 22936900 options (at most 16384)");
  mtg::observation_t text = sent[1];
  text.text_ops.clear();
  text.text.clear();
  for (int i = 0; i < 700; ++i) text.text_ops.insert(text.text_ops.end(), {0, 32767});
  text.n_text_ops = static_cast<int32_t>(text.text_ops.size());
  refused(text, "its text would be 22936900 bytes (at most 1048576)");

  ObservationReader reader;
  mtg::observation_t forged = step_observation(0, false);
  mtg::image_t im = sample_image(100);
  im.content_hash = to_hex(fnv1a64(im.data));
  im.data[50] ^= 1;  // the bytes changed, the name did not
  forged.images = {im};
  forged.n_images = 1;
  try {
    reader.whole(forged, codec);
    ADD_FAILURE() << "an image that is not its hash's was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is not the image its content hash"), std::string::npos) << e.what();
  }
}

// lcm-gen's decoders sized an array from its count before reading it: an image_t of 50 bytes
// claiming 2^31-1 bytes of data took 2 GB, a negative count or a string length of 0 threw
// through liblcm (abort). lcmtypes/bound_decoders.cmake makes them refuse such counts first.
TEST(BoundedDecoders, CountsBeyondTheMessageAreRefusedBeforeAnythingIsAllocated) {
  mtg::image_t im{};
  im.role = "view";
  im.encoding = "png";
  im.content_hash = "0";
  auto bytes = encode(im);  // ends with nbytes = 0 (no data)
  auto with_count = [&](std::int32_t n) {
    auto b = bytes;
    const auto u = static_cast<std::uint32_t>(n);
    for (int i = 0; i < 4; ++i) b[b.size() - 4 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(u >> (24 - 8 * i));
    return b;
  };
  for (const std::int32_t n : {std::int32_t{2147483647}, std::int32_t{-1}, std::int32_t{1}}) {
    const auto b = with_count(n);
    mtg::image_t back{};
    EXPECT_EQ(back.decode(b.data(), 0, static_cast<int>(b.size())), -1) << "count " << n;
    EXPECT_LT(back.data.capacity(), 2u) << "count " << n << " allocated before it was checked";
  }
  // The role's length (right after the 8-byte type hash): 0 and -5 are no strings.
  for (const std::int32_t n : {0, -5}) {
    auto b = bytes;
    const auto u = static_cast<std::uint32_t>(n);
    for (int i = 0; i < 4; ++i) b[8 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(u >> (24 - 8 * i));
    mtg::image_t back{};
    EXPECT_EQ(back.decode(b.data(), 0, static_cast<int>(b.size())), -1) << "string length " << n;
  }
  mtg::image_t whole{};
  EXPECT_EQ(whole.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
}

TEST(ObservationPacking, AnImageSentEarlierInTheAttemptGoesByReferenceAndComesBackWhole) {
  WordsCodec codec;
  SentImages sent;
  ObservationReader reader;
  auto with_images = [](int step, std::vector<int> sizes) {
    mtg::observation_t o = step_observation(step, false);
    for (int n : sizes) {
      mtg::image_t im = sample_image(n);
      im.content_hash = to_hex(fnv1a64(im.data));
      o.images.push_back(im);
    }
    o.n_images = static_cast<int32_t>(o.images.size());
    return o;
  };
  // Step 0: two views; the second repeats the first within the observation.
  mtg::observation_t o0 = with_images(0, {100, 200, 100});
  const mtg::observation_t made0 = o0;
  sent.refer_to_earlier(o0);
  EXPECT_EQ(o0.images[0].nbytes, 100);
  EXPECT_EQ(o0.images[1].nbytes, 200);
  EXPECT_EQ(o0.images[2].nbytes, 0);
  EXPECT_EQ(encode(reader.whole(through_the_bus(o0), codec)), encode(made0));
  // Step 1: the view of 200 bytes did not change; a new one did.
  mtg::observation_t o1 = with_images(1, {200, 300});
  const mtg::observation_t made1 = o1;
  sent.refer_to_earlier(o1);
  EXPECT_EQ(o1.images[0].nbytes, 0);
  EXPECT_TRUE(o1.images[0].data.empty());
  EXPECT_EQ(o1.images[0].role, made1.images[0].role);
  EXPECT_EQ(o1.images[1].nbytes, 300);
  EXPECT_EQ(encode(reader.whole(through_the_bus(o1), codec)), encode(made1));
  // A resent step 1 (its first copy may have been lost) refers only to step 0.
  mtg::observation_t again = with_images(1, {200, 300});
  sent.refer_to_earlier(again);
  EXPECT_EQ(again.images[0].nbytes, 0);
  EXPECT_EQ(again.images[1].nbytes, 300);
  // Another attempt of the episode starts from nothing.
  mtg::observation_t other = with_images(0, {200});
  other.header.attempt = 2;
  sent.refer_to_earlier(other);
  EXPECT_EQ(other.images[0].nbytes, 200);
  // A reference a reader cannot resolve is an error naming the image.
  ObservationReader fresh;
  try {
    fresh.whole(o1, codec);
    ADD_FAILURE() << "resolved an image never carried";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("refers to image " + to_hex(fnv1a64(sample_image(200).data))), std::string::npos)
        << e.what();
  }
  // The attempt's last observation forgets it.
  mtg::observation_t last = with_images(2, {});
  last.header.attempt = 2;
  last.done = true;
  sent.refer_to_earlier(last);
  EXPECT_EQ(sent.attempts(), 0u);
}

}  // namespace
}  // namespace mtg::bus
