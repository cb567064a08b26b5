// The renderer as a process on the bus: a bad request (unknown platform, missing mesh, zero-size
// image) gets a reply with a one-line error and the process serves the next request; and a
// rendered benchmark run gives the agent images in its observations.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <set>

#include "bus/bus.h"
#include "bus/header.h"
#include "bus/channels.h"
#include "bus/recording.h"
#include "bus/url.h"
#include "core/tasks/generator.h"
#include "core/tasks/task_db.h"
#include "mtg/heartbeat_t.hpp"
#include "bus/observation_packing.h"
#include "mtg/observation_t.hpp"
#include "mtg/render_request_t.hpp"
#include "mtg/render_result_t.hpp"
#include "orchestrator/run/results_db.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/process.h"

namespace mtg {
namespace {

using ::testing::HasSubstr;

class RenderServiceTest : public ::testing::Test {
 protected:
  void SetUp() override { built_ = testing::render_room(fx_); }

  std::string object_named(const std::string& template_name) const {
    const graph::ObjectId i = testing::object_of_template(built_.graph, template_name);
    return i.valid() ? built_.graph.objects[i].name : "";
  }
  std::string table_top() const {
    const graph::PlatformId p = testing::navigable_platform_of(built_.graph, "toy_wood_table");
    return p.valid() ? built_.graph.platforms[p].name : "";
  }

  mtg::render_request_t request(std::int64_t id, mtg::render_view_t view) const {
    mtg::render_request_t r{};
    r.header = bus::HeaderStamper("", "render_service_test").next(bus::EpisodeId(7));  // a header of this schema
    r.request_id = id;
    r.scene = "render_room";
    r.data_dir = fx_.root().string();
    r.width = 320;
    r.height = 240;
    r.encoding = "png";
    r.views = {std::move(view)};
    r.n_views = 1;
    return r;
  }

  static mtg::render_view_t view(const std::string& kind, const std::string& platform, const std::string& item,
                                 const std::string& marks) {
    mtg::render_view_t v{};
    v.view = kind;
    v.platform = platform;
    v.side = -1;
    v.item = item;
    v.marks = marks;
    return v;
  }

  testing::FixtureDataset fx_;
  testing::BuiltScene built_;
};

TEST_F(RenderServiceTest, BadRequestsGetErrorRepliesAndTheRendererKeepsServing) {
  bus::Bus bus(bus::kDefaultUrl);
  bool ready = false;
  std::map<std::int64_t, mtg::render_result_t> replies;
  bus.subscribe<mtg::heartbeat_t>(bus::kHeartbeat, [&](const std::string&, const mtg::heartbeat_t& m) {
    ready = ready || m.role == "renderer";
  });
  bus.subscribe<mtg::render_result_t>(bus::kRenderResult, [&](const std::string&, const mtg::render_result_t& m) {
    replies[m.request_id] = m;
  });
  testing::ChildProcess renderer({testing::bin("mtg_renderer"), "--url", bus::kDefaultUrl, "--profile", "none"},
                                 (fx_.root() / "renderer.log").string());
  ASSERT_TRUE(bus.handle_until([&] { return ready; }, 30000)) << "the renderer sent no heartbeat";

  bus.publish(bus::kRenderRequest, request(1, view("platform", "no_such_platform", "", "items")));
  auto zero = request(2, view("platform", table_top(), "", "items"));
  zero.width = 0;
  bus.publish(bus::kRenderRequest, zero);
  bus.publish(bus::kRenderRequest, request(3, view("item", "", object_named("toy_ghost"), "")));
  bus.publish(bus::kRenderRequest, request(4, view("platform", table_top(), "", "items")));
  ASSERT_TRUE(bus.handle_until([&] { return replies.size() == 4; }, 60000)) << replies.size() << " replies";

  EXPECT_FALSE(replies[1].ok);
  EXPECT_THAT(replies[1].error, HasSubstr("no platform 'no_such_platform'"));
  EXPECT_FALSE(replies[2].ok);
  EXPECT_THAT(replies[2].error, HasSubstr("image size 0x240"));
  EXPECT_FALSE(replies[3].ok);
  EXPECT_THAT(replies[3].error, HasSubstr("has no mesh to draw"));
  for (const std::int64_t id : {1, 2, 3}) {
    EXPECT_EQ(replies[id].n_images, 0);
    EXPECT_EQ(replies[id].header.episode_id, 7) << "a reply names the requester's episode";
  }
  const mtg::render_result_t& good = replies[4];
  ASSERT_TRUE(good.ok) << good.error;
  ASSERT_EQ(good.n_images, 2);
  EXPECT_EQ(good.images[0].role, "view");
  EXPECT_EQ(good.images[1].role, "view_marked");
  const cv::Mat png = cv::imdecode(good.images[1].data, cv::IMREAD_COLOR);
  EXPECT_EQ(png.cols, 320);
  EXPECT_EQ(png.rows, 240);
  EXPECT_TRUE(renderer.running());
}

TEST_F(RenderServiceTest, ARenderedRunGivesTheAgentImagesAtEveryStep) {
  tasks::TaskOptions options;
  options.levels = {1};
  const auto generated = tasks::generate_tasks(built_.scene, built_.graph, options);
  const std::string db = (fx_.root() / "tasks.sqlite").string();
  tasks::write_task_db(db, {generated.set}, generated.votes, options);
  const auto out = fx_.root() / "run";
  testing::ChildProcess run({testing::bin("mtg"), "run", "--tasks", db, "--agent", "oracle", "--limit", "3",
                             "--parallel", "2", "--render", "--image-size", "320x240", "--out", out.string(), "--data",
                             fx_.root().string(), "--profile", "none", "--no-progress"},
                            (fx_.root() / "mtg.log").string());
  ASSERT_EQ(run.wait(120000), 0) << "see " << (fx_.root() / "mtg.log");
  const auto rows = orchestrator::read_results(out / "results.sqlite");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& r : rows) EXPECT_TRUE(r.success) << r.task_id << ": " << r.detail;

  int observations = 0, with_images = 0, marked = 0, published = 0, by_reference = 0;
  bus::RecordedObservations recorded;  // packed on the bus: made whole as an agent gets them
  std::map<std::pair<std::int64_t, int>, std::set<std::string>> whole_images;  // (episode, attempt) -> hashes
  bus::for_each_recorded_event(out, [&](const lcm::LogEvent& ev) {
    if (ev.channel == bus::kRenderResult) {  // each image once: in the observation, not here too
      mtg::render_result_t result{};
      ASSERT_GE(result.decode(ev.data, 0, ev.datalen), 0);
      EXPECT_EQ(result.n_images, 0);
      published += result.images_published;
      return;
    }
    if (!bus::is_episode_channel(ev.channel, bus::EpisodeStream::kObservation)) return;
    mtg::observation_t packed{};
    ASSERT_GE(packed.decode(ev.data, 0, ev.datalen), 0);
    // Each image is recorded once per attempt: a view shown again comes by reference.
    auto& carried = whole_images[{packed.header.episode_id, packed.header.attempt}];
    for (const auto& img : packed.images) {
      if (img.nbytes == 0) {
        ++by_reference;
        EXPECT_EQ(carried.count(img.content_hash), 1u) << "step " << packed.step << " refers to an image not carried";
      } else {
        EXPECT_TRUE(carried.insert(img.content_hash).second)
            << "step " << packed.step << " of episode " << packed.header.episode_id << " carries an image again";
      }
    }
    const mtg::observation_t obs = recorded.whole(packed).value();
    ++observations;
    if (obs.done) {
      EXPECT_EQ(obs.n_images, 0) << "the final observation needs no picture";
      return;
    }
    EXPECT_GE(obs.n_images, 2) << "step " << obs.step << " of episode " << obs.header.episode_id;
    if (obs.n_images > 0) ++with_images;
    for (const auto& img : obs.images) {
      marked += img.role.ends_with("_marked");
      const cv::Mat m = cv::imdecode(img.data, cv::IMREAD_COLOR);
      EXPECT_EQ(m.cols, 320);
      EXPECT_EQ(m.rows, 240);
    }
  });
  EXPECT_GT(observations, 6);
  EXPECT_EQ(with_images, observations - 3);
  EXPECT_GE(marked, with_images);
  EXPECT_GE(published, 2 * with_images);
  EXPECT_GT(by_reference, 0) << "the oracle's views repeat (the start view, a platform seen twice)";
}

// A pool of renderers (core/render/render_pool.h): three renderers give every observation the
// images one renderer gives, byte for byte, and each of them draws; one that dies with a request
// unanswered is replaced, its request goes to the new one, and no episode is run again.
TEST_F(RenderServiceTest, APoolOfRenderersGivesOneRenderersImagesAndOutlivesADeadOne) {
  tasks::TaskOptions options;
  options.levels = {1};
  const auto generated = tasks::generate_tasks(built_.scene, built_.graph, options);
  const std::string db = (fx_.root() / "tasks.sqlite").string();
  tasks::write_task_db(db, {generated.set}, generated.votes, options);
  const auto run = [&](const std::string& name, int renderers, const std::map<std::string, std::string>& env) {
    const auto out = fx_.root() / name;
    for (const auto& [k, v] : env) ::setenv(k.c_str(), v.c_str(), 1);  // the run's processes inherit it
    testing::ChildProcess p({testing::bin("mtg"), "run", "--tasks", db, "--agent", "oracle", "--limit", "6",
                             "--parallel", "4", "--render", "--renderers", std::to_string(renderers), "--image-size",
                             "320x240", "--out", out.string(), "--data", fx_.root().string(), "--profile", "none",
                             "--no-progress"},
                            (fx_.root() / (name + ".log")).string());
    EXPECT_EQ(p.wait(180000), 0) << "see " << (fx_.root() / (name + ".log"));
    for (const auto& [k, v] : env) ::unsetenv(k.c_str());
    return out;
  };
  // (episode, step) -> the content hashes of its images, in order; and who drew them.
  using Images = std::map<std::pair<std::int64_t, int>, std::vector<std::string>>;
  const auto images_of = [](const std::filesystem::path& out, std::set<std::string>& renderers) {
    Images images;
    bus::RecordedObservations recorded;
    bus::for_each_recorded_event(out, [&](const lcm::LogEvent& ev) {
      if (ev.channel == bus::kRenderResult) {
        mtg::render_result_t r{};
        if (r.decode(ev.data, 0, ev.datalen) >= 0 && r.ok) renderers.insert(r.header.sender.substr(0, r.header.sender.find(':')));
        return;
      }
      if (!bus::is_episode_channel(ev.channel, bus::EpisodeStream::kObservation)) return;
      mtg::observation_t packed{};
      ASSERT_GE(packed.decode(ev.data, 0, ev.datalen), 0);
      const mtg::observation_t obs = recorded.whole(packed).value();
      if (obs.n_images == 0) return;
      auto& hashes = images[{obs.header.episode_id, obs.step}];
      hashes.clear();  // a step drawn twice (its request sent again) shows what the agent saw last
      for (const auto& img : obs.images) hashes.push_back(img.role + " " + img.content_hash);
    });
    return images;
  };
  const auto one = run("one", 1, {});
  const auto marks = fx_.root() / "marks";
  std::filesystem::create_directories(marks);
  const auto three = run("three", 3, {{"MTG_FAULTS", "renderer_dies:1"}, {"MTG_FAULT_MARKS", marks.string()}});

  std::set<std::string> drew_one, drew_three;
  const Images a = images_of(one, drew_one), b = images_of(three, drew_three);
  EXPECT_EQ(drew_one, (std::set<std::string>{"renderer"}));
  EXPECT_EQ(drew_three, (std::set<std::string>{"renderer", "renderer-1", "renderer-2"})) << "every renderer draws";
  EXPECT_GT(a.size(), 12u);
  EXPECT_EQ(a, b) << "the same images whatever the pool";

  EXPECT_TRUE(std::filesystem::exists(marks / "renderer_dies")) << "renderer-1 was to die once";
  const auto rows_one = orchestrator::read_results(one / "results.sqlite");
  const auto rows_three = orchestrator::read_results(three / "results.sqlite");
  ASSERT_EQ(rows_three.size(), 6u);
  ASSERT_EQ(rows_one.size(), 6u);
  for (std::size_t i = 0; i < rows_three.size(); ++i) {
    EXPECT_EQ(orchestrator::verdict_fingerprint(rows_three[i]), orchestrator::verdict_fingerprint(rows_one[i]));
    EXPECT_EQ(rows_three[i].attempt, 0) << "episode " << rows_three[i].episode_id.value() << " was run again";
  }
  std::ifstream log(three / "logs" / "scene_graph.log");
  const std::string text((std::istreambuf_iterator<char>(log)), {});
  EXPECT_THAT(text, HasSubstr("renderer-1 was restarted; asking it again"));
}

// The fixture's Level 2 tasks (each names look-alikes) in a task database, and oracle runs of
// them with images.
struct LookalikeFixture {
  testing::FixtureDataset fx;
  std::string db;
  std::vector<tasks::Task> tasks;

  LookalikeFixture() {
    const auto b = testing::two_tables(fx);
    tasks::TaskOptions options;
    options.levels = {2};
    const auto generated = tasks::generate_tasks(b.scene, b.graph, options);
    db = (fx.root() / "tasks.sqlite").string();
    tasks::write_task_db(db, {generated.set}, generated.votes, options);
    tasks = generated.set.tasks;
  }
  const tasks::Task& task(const std::string& id) const {
    return *std::find_if(tasks.begin(), tasks.end(), [&](const tasks::Task& t) { return t.id == id; });
  }
  // Runs the oracle on `limit` tasks into `out` (with `extra` options); every episode succeeds.
  // Returns each episode's task id.
  std::map<std::int64_t, std::string> run_oracle(const std::filesystem::path& out, int limit,
                                                 const std::vector<std::string>& extra) const {
    std::vector<std::string> argv = {testing::bin("mtg"), "run", "--tasks", db, "--agent", "oracle", "--limit",
                                     std::to_string(limit), "--levels", "2", "--render", "--image-size", "320x240",
                                     "--out", out.string(), "--data", fx.root().string(), "--profile", "none",
                                     "--no-progress"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    const std::string log = out.string() + ".log";
    testing::ChildProcess run(argv, log);
    EXPECT_EQ(run.wait(120000), 0) << "see " << log;
    std::map<std::int64_t, std::string> task_of;
    const auto rows = orchestrator::read_results(out / "results.sqlite");
    EXPECT_EQ(rows.size(), static_cast<std::size_t>(limit));
    for (const auto& r : rows) {
      EXPECT_TRUE(r.success) << r.task_id << ": " << r.detail;
      task_of[r.episode_id.value()] = r.task_id;
    }
    return task_of;
  }
};

// Each observation a run recorded, whole (packed ones unpacked).
void for_each_observation(const std::filesystem::path& run, const std::function<void(const mtg::observation_t&)>& f) {
  bus::RecordedObservations recorded;
  bus::for_each_recorded_event(run, [&](const lcm::LogEvent& ev) {
    if (!bus::is_episode_channel(ev.channel, bus::EpisodeStream::kObservation)) return;
    mtg::observation_t packed{};
    ASSERT_GE(packed.decode(ev.data, 0, ev.datalen), 0);
    f(recorded.whole(packed).value());
  });
}

// Look-alikes are shown, not only named: the first observation of a task about one of three
// identical boxes carries a close-up of the box meant (role "focus") and a hint naming it.
// The look-alikes' close-ups come with the first observation and again where the robot stands at
// their platform, without a number (the paper's aid to find the object, not its key); the held
// item's close-up says the number it was picked as.
TEST(LookalikeCloseUps, TheFirstObservationShowsAndNamesEachLookalike) {
  const LookalikeFixture lf;
  const testing::FixtureDataset& fx = lf.fx;
  const auto out = fx.root() / "run";
  const std::map<std::int64_t, std::string> task_of = lf.run_oracle(out, 3, {"--parallel", "2"});
  ASSERT_EQ(task_of.size(), 3u);
  int first_observations = 0;
  std::size_t images = 0, most_close_ups = 0;
  for_each_observation(out, [&](const mtg::observation_t& obs) {
    std::size_t focus = 0;
    for (const auto& img : obs.images) {
      if (img.role == "focus") {
        ++focus;
        // Where it stands, and no number: the number belongs to the platform view.
        EXPECT_THAT(img.caption, ::testing::HasSubstr("The object the task calls '")) << img.caption;
        EXPECT_THAT(img.caption, ::testing::HasSubstr("where it stands")) << img.caption;
        EXPECT_THAT(img.caption, ::testing::Not(::testing::ContainsRegex("(object|number) [0-9]"))) << img.caption;
      }
      if (img.role == "item") {
        EXPECT_THAT(img.caption, ::testing::HasSubstr("where you picked it up")) << img.caption;
      }
      images += img.nbytes > 0 ? 1 : 0;
    }
    most_close_ups = std::max(most_close_ups, focus);
    if (obs.step != 0) {
      // Later, only where the robot stands at a look-alike's platform.
      if (focus > 0) {
        EXPECT_THAT(obs.text, ::testing::HasSubstr("You are standing at")) << obs.text;
      }
      return;
    }
    ++first_observations;
    const std::size_t expected = lf.task(task_of.at(obs.header.episode_id)).identify.size();
    EXPECT_GE(expected, 1u);
    EXPECT_EQ(focus, expected) << obs.task_text;
    EXPECT_THAT(obs.hint, ::testing::HasSubstr("look-alikes")) << obs.hint;
    EXPECT_THAT(obs.hint, ::testing::HasSubstr("lose-up"));
  });
  EXPECT_EQ(first_observations, 3);

  // mtg images writes every one of them to a file of its own, two close-ups of one step included.
  ASSERT_GE(most_close_ups, 2u) << "the fixture names an item and an anchor with look-alikes";
  const auto folder = fx.root() / "images";
  ASSERT_EQ(testing::ChildProcess({testing::bin("mtg"), "images", out.string(), "--out", folder.string()},
                                  (fx.root() / "images.log").string())
                .wait(60000),
            0);
  const auto files = static_cast<std::size_t>(
      std::distance(std::filesystem::directory_iterator(folder), std::filesystem::directory_iterator()));
  EXPECT_EQ(files, images);
}

// The look-alike aid a run asks for (--lookalike-aid) is what its episodes give, recorded in its
// plan: words alone send no close-up and keep the text; close-ups alone call each look-alike "the
// box in close-up k", never by its words, and caption its close-up so; image without images is
// refused with one line. The oracle succeeds either way: the aid changes what is said, not what
// is judged.
TEST(LookalikeCloseUps, WordsAloneOrCloseUpsAloneAsThePlanSays) {
  const LookalikeFixture lf;
  const testing::FixtureDataset& fx = lf.fx;
  const std::string& db = lf.db;
  for (const std::string aid : {"words", "image"}) {
    SCOPED_TRACE(aid);
    const auto out = fx.root() / ("run_" + aid);
    const std::map<std::int64_t, std::string> task_of = lf.run_oracle(out, 2, {"--lookalike-aid", aid});
    ASSERT_EQ(task_of.size(), 2u);
    std::ifstream plan_file(out / "plan.json");
    EXPECT_EQ(nlohmann::json::parse(plan_file).at("lookalike_aid"), aid);
    int first = 0;
    std::size_t close_ups = 0;
    for_each_observation(out, [&](const mtg::observation_t& obs) {
      for (const auto& img : obs.images) {
        if (img.role != "focus") continue;
        ++close_ups;
        EXPECT_THAT(img.caption, ::testing::StartsWith("Close-up ")) << img.caption;
        EXPECT_THAT(img.caption, ::testing::HasSubstr(" the task means")) << img.caption;
      }
      if (obs.step != 0) return;
      ++first;
      const tasks::Task& task = lf.task(task_of.at(obs.header.episode_id));
      ASSERT_FALSE(task.identify.empty());
      EXPECT_THAT(obs.hint, ::testing::HasSubstr("look-alikes")) << obs.hint;
      if (aid == "words") {
        EXPECT_EQ(obs.task_text, task.text);
        EXPECT_THAT(obs.hint, ::testing::HasSubstr(task.identify.front().phrase));
        EXPECT_THAT(obs.hint, ::testing::Not(::testing::HasSubstr("lose-up"))) << obs.hint;
      } else {
        EXPECT_THAT(obs.task_text, ::testing::HasSubstr(" in close-up 1")) << obs.task_text;
        for (const auto& id : task.identify) {
          EXPECT_THAT(obs.task_text, ::testing::Not(::testing::HasSubstr(id.phrase))) << obs.task_text;
          EXPECT_THAT(obs.hint, ::testing::Not(::testing::HasSubstr(id.phrase))) << obs.hint;
        }
      }
    });
    EXPECT_EQ(first, 2);
    if (aid == "words") {
      EXPECT_EQ(close_ups, 0u);
    } else {
      EXPECT_GE(close_ups, 2u);
    }
  }
  const auto refused = fx.root() / "refused.log";
  EXPECT_NE(testing::ChildProcess({testing::bin("mtg"), "run", "--tasks", db, "--agent", "oracle", "--limit", "1",
                                   "--lookalike-aid", "image", "--out", (fx.root() / "run_refused").string(),
                                   "--data", fx.root().string(), "--profile", "none", "--no-progress"},
                                  refused.string())
                .wait(60000),
            0);
  std::ifstream log(refused);
  EXPECT_THAT(std::string((std::istreambuf_iterator<char>(log)), {}),
              ::testing::HasSubstr("--lookalike-aid image needs images"));
}

}  // namespace
}  // namespace mtg
