// lcm-spy decodes the project's messages: one message of every mtg type, recorded in an LCM log
// here, is decoded by the Java bindings in the type jar (tests/java/DecodeAll.java, headless).
// DecodeAll also fails when the jar holds a type this test did not record, so a new type
// cannot be forgotten here.

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <filesystem>
#include <fstream>

#include "bus/observation_packing.h"
#include "mtg/action_option_t.hpp"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_result_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"
#include "mtg/error_event_t.hpp"
#include "mtg/header_t.hpp"
#include "mtg/heartbeat_t.hpp"
#include "mtg/image_t.hpp"
#include "mtg/judge_event_t.hpp"
#include "mtg/lease_renewal_t.hpp"
#include "mtg/lease_t.hpp"
#include "mtg/recorded_t.hpp"
#include "mtg/object_placement_t.hpp"
#include "mtg/observation_t.hpp"
#include "mtg/action_list_t.hpp"
#include "mtg/rate_limit_t.hpp"
#include "mtg/record_chunk_t.hpp"
#include "mtg/recording_ref_t.hpp"
#include "mtg/recording_request_t.hpp"
#include "mtg/render_request_t.hpp"
#include "mtg/render_result_t.hpp"
#include "mtg/render_view_t.hpp"
#include "mtg/run_control_t.hpp"
#include "mtg/run_info_t.hpp"
#include "mtg/scene_request_t.hpp"
#include "mtg/scene_summary_t.hpp"
#include "mtg/state_update_t.hpp"
#include "mtg/task_set_request_t.hpp"
#include "mtg/task_set_summary_t.hpp"
#include "mtg/task_t.hpp"
#include "mtg/world_state_delta_t.hpp"
#include "tests/support/fixture_dataset.h"
#include "tests/support/process.h"

namespace mtg {
namespace {

class LogWriter {
 public:
  explicit LogWriter(const std::string& path) : log_(path, "w") {}
  template <class Msg>
  void add(const std::string& channel, const Msg& msg) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
    ASSERT_GE(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())), 0) << channel;
    lcm::LogEvent ev;
    ev.eventnum = n_++;
    ev.timestamp = 1000 * n_;
    ev.channel = channel;
    ev.datalen = static_cast<int32_t>(bytes.size());
    ev.data = bytes.data();
    ASSERT_EQ(log_.writeEvent(&ev), 0);
  }

 private:
  lcm::LogFile log_;
  std::int64_t n_ = 0;
};

template <class Msg>
Msg with_header() {
  Msg m{};
  m.header.run_id = "java-check";
  m.header.episode_id = 7;
  m.header.sender = "test:0";
  m.header.schema_version = 1;
  return m;
}

TEST(LcmSpyTypes, TheJavaBindingsDecodeOneRecordedMessageOfEveryType) {
  testing::FixtureDataset dir;  // a scratch folder removed afterwards
  const std::string log = (dir.root() / "every_type.lcmlog").string();
  {
    LogWriter w(log);
    mtg::image_t image{};
    image.width = 2;
    image.height = 1;
    image.encoding = "png";
    image.data = {1, 2, 3};
    image.nbytes = 3;
    mtg::action_option_t option{};
    option.key = "l1";
    option.description = "go to the table";
    auto obs = with_header<mtg::observation_t>();
    obs.actions = {option};
    obs.n_actions = 1;
    obs.images = {image};
    obs.n_images = 1;
    mtg::action_list_t list{};  // what a packed observation's zactions hold (schema 7)
    list.actions = obs.actions;
    list.n_actions = 1;
    w.add("NESTED_ACTIONS", list);
    bus::WordsCodec codec;
    bus::WordsPacker packer;
    packer.pack(obs, codec);  // as it travels
    w.add("MTG_OBS", obs);
    w.add("MTG_ACT", with_header<mtg::agent_action_t>());
    mtg::object_placement_t placed{};
    placed.object = "cube";
    placed.footprint_x = {0.0, 1.0, 1.0};
    placed.footprint_y = {0.0, 0.0, 1.0};
    placed.n_vertices = 3;
    auto state = with_header<mtg::state_update_t>();
    state.moved = {placed};
    state.n_moved = 1;
    w.add("MTG_STATE", state);
    w.add("MTG_JUDGE", with_header<mtg::judge_event_t>());
    auto start = with_header<mtg::episode_start_t>();
    start.task.task_id = "fixture/L1/000001";
    w.add("MTG_EPISODE_START", start);
    auto truth = with_header<mtg::episode_truth_t>();
    truth.oracle_plan = {"l1", "o1", "0"};
    truth.n_oracle = 3;
    w.add("MTG_EPISODE_TRUTH", truth);
    w.add("MTG_RESULT", with_header<mtg::episode_result_t>());
    w.add("MTG_RECORDED", with_header<mtg::recorded_t>());
    mtg::render_view_t view{};
    view.view = "platform";
    auto request = with_header<mtg::render_request_t>();
    request.views = {view};
    request.n_views = 1;
    w.add("MTG_RENDER_REQ", request);
    auto rendered = with_header<mtg::render_result_t>();
    rendered.images = {image};
    rendered.n_images = 1;
    w.add("MTG_RENDER_RES", rendered);
    w.add("MTG_HEARTBEAT", with_header<mtg::heartbeat_t>());
    w.add("MTG_LEASE", with_header<mtg::lease_t>());
    w.add("MTG_RUN", with_header<mtg::run_info_t>());
    auto chunk = with_header<mtg::record_chunk_t>();
    chunk.data = {9, 9};
    chunk.size = 2;
    w.add("MTG_RECORD", chunk);
    auto renewal = with_header<mtg::lease_renewal_t>();
    renewal.episode_ids = {3, 4};
    renewal.attempts = {0, 1};
    renewal.n_leases = 2;
    w.add("MTG_LEASE_RENEW", renewal);
    auto ref = with_header<mtg::recording_ref_t>();
    ref.location = "/shared/run/E3-a0.lcmlog";
    ref.sha256 = std::string(64, 'a');
    w.add("MTG_RECORD_REF", ref);
    auto wanted = with_header<mtg::recording_request_t>();
    wanted.locations = {"/w/run/episodes/E3-a0.lcmlog"};
    wanted.episode_ids = {3};
    wanted.attempts = {0};
    wanted.n_files = 1;
    w.add("MTG_RECORD_REQ", wanted);
    w.add("MTG_RATE", with_header<mtg::rate_limit_t>());
    w.add("MTG_CONTROL", with_header<mtg::run_control_t>());
    w.add("MTG_ERROR", with_header<mtg::error_event_t>());
    w.add("MTG_SCENE_REQ", with_header<mtg::scene_request_t>());
    w.add("MTG_SCENE_SUMMARY", with_header<mtg::scene_summary_t>());
    w.add("MTG_TASKSET_REQ", with_header<mtg::task_set_request_t>());
    w.add("MTG_TASKSET_SUMMARY", with_header<mtg::task_set_summary_t>());
    // The nested types, each on its own.
    w.add("NESTED_HEADER", start.header);
    w.add("NESTED_TASK", start.task);
    w.add("NESTED_IMAGE", image);
    w.add("NESTED_OPTION", option);
    w.add("NESTED_PLACEMENT", placed);
    w.add("NESTED_VIEW", view);
    mtg::world_state_delta_t delta{};  // a render request's world state, and its parts
    delta.held = "cup_1";
    delta.moved.resize(1);
    delta.moved[0].object = "cup_1";
    delta.moved[0].n_vertices = 1;
    delta.moved[0].footprint_x = {0.5};
    delta.moved[0].footprint_y = {-0.5};
    delta.n_moved = 1;
    delta.reordered = {{"table_1", 1, {"cup_2"}}};
    delta.n_reordered = 1;
    delta.offsets.resize(1);
    delta.offsets[0].platform = "tray_1_platform";
    delta.n_offsets = 1;
    w.add("NESTED_STATE", delta);
    w.add("NESTED_MOVED", delta.moved[0]);
    w.add("NESTED_ORDER", delta.reordered[0]);
    w.add("NESTED_OFFSET", delta.offsets[0]);
  }
  const std::string out = (dir.root() / "java.out").string();
  testing::ChildProcess java({"/usr/bin/java", "-cp", std::string(MTG_LCM_JAVA_JAR) + ":" + MTG_TYPES_JAR + ":" +
                              MTG_JAVA_TEST_CLASSES, "DecodeAll", log, MTG_TYPES_JAR}, out);
  const int status = java.wait(60000);
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  ASSERT_EQ(status, 0) << text;
  // Every type of lcmtypes/, so a new one cannot go without a case above.
  std::size_t types = 0;
  for (const auto& f : std::filesystem::directory_iterator(std::filesystem::path(MTG_SOURCE_DIR) / "lcmtypes")) {
    types += f.path().extension() == ".lcm" ? 1 : 0;
  }
  EXPECT_NE(text.find("ALL " + std::to_string(types) + " types decoded"), std::string::npos) << text;
  EXPECT_NE(text.find("DECODED observation_t MTG_OBS run=java-check"), std::string::npos) << text;
  EXPECT_NE(text.find("DECODED record_chunk_t MTG_RECORD run=java-check"), std::string::npos) << text;
}

}  // namespace
}  // namespace mtg
