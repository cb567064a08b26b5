// Drawing samples (core/tasks/draw.h) and suites as files (core/tasks/suite.h).

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/tasks/draw.h"
#include "core/tasks/suite.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/rng.h"

namespace mtg::tasks {
namespace {

namespace fs = std::filesystem;

Task atomic(int index, const std::string& source, const std::string& item, int level = 2) {
  Task t;
  char id[32];
  std::snprintf(id, sizeof id, "apt/L%d/%06d", level, index);
  t.id = id;
  t.scene = "apt";
  t.level = level;
  t.type = "surface";
  t.text = "move " + item + " from " + source;
  t.item = item;
  t.source = source;
  t.destination = "shelf_platform_0";
  t.goal = {{"atomic", {{"type", "surface"}, {"item", item}, {"source", source}, {"platform", "shelf_platform_0"}}}};
  t.oracle = {"l1", "o1", "l2", "startplace", "1", "0"};
  return t;
}

// A lopsided Level 2 like a kitchen counter's: 90 tasks on one platform (nine item models), and
// ten other platforms with ten tasks each.
std::vector<Task> lopsided() {
  std::vector<Task> out;
  int i = 0;
  for (int k = 0; k < 90; ++k) out.push_back(atomic(i++, "counter_platform_0", "model" + std::to_string(k % 9) + "_" + std::to_string(k)));
  for (int p = 0; p < 10; ++p) {
    for (int k = 0; k < 10; ++k) out.push_back(atomic(i++, "table" + std::to_string(p) + "_platform_0", "cup_01_" + std::to_string(k)));
  }
  return out;
}

std::vector<const Task*> pointers(const std::vector<Task>& tasks) {
  std::vector<const Task*> out;
  for (const Task& t : tasks) out.push_back(&t);
  return out;
}

TEST(Draw, StratifiedDealsEveryPlatformItsTurnUniformFollowsTheSetsShape) {
  const auto all = lopsided();
  // Uniform: the counter is 47 % of the set (90 of 190), and about that of the sample.
  const auto uniform = draw_tasks(pointers(all), 22, DrawKind::kUniform, 7);
  // Stratified: 11 platforms, 22 tasks: two each.
  const auto stratified = draw_tasks(pointers(all), 22, DrawKind::kStratified, 7);
  ASSERT_EQ(stratified.size(), 22u);
  std::map<std::string, int> per_platform;
  for (const Task* t : stratified) ++per_platform[t->source];
  EXPECT_EQ(per_platform.size(), 11u);
  for (const auto& [platform, n] : per_platform) EXPECT_EQ(n, 2) << platform;
  // The counter's two are of two different item models (round-robin within the platform).
  std::set<std::string> models;
  for (const Task* t : stratified) {
    if (t->source == "counter_platform_0") models.insert(stratum_of(*t).secondary);
  }
  EXPECT_EQ(models.size(), 2u);
  const auto spread_u = spread_of(uniform).at(2), spread_s = spread_of(stratified).at(2);
  EXPECT_GT(spread_u.biggest_share(), 0.35);
  EXPECT_NEAR(spread_s.biggest_share(), 2.0 / 22.0, 1e-12);
  EXPECT_EQ(spread_s.strata, 11);
  // Id order, no task twice, and the same draw for the same seed.
  for (std::size_t i = 1; i < stratified.size(); ++i) EXPECT_LT(stratified[i - 1]->id, stratified[i]->id);
  EXPECT_EQ(stratified, draw_tasks(pointers(all), 22, DrawKind::kStratified, 7));
  EXPECT_NE(stratified, draw_tasks(pointers(all), 22, DrawKind::kStratified, 8));
}

// Plans made before stratification say "uniform" and mean the draw they made: a seeded shuffle of
// the group in id order, cut to n, back in id order.
TEST(Draw, UniformIsTheDrawRunsMadeBefore) {
  const auto all = lopsided();
  std::vector<const Task*> legacy = pointers(all);
  Rng rng(derive_seed(3, fnv1a64(std::string("apt/L2"))));
  rng.shuffle(legacy);
  legacy.resize(15);
  std::sort(legacy.begin(), legacy.end(), [](const Task* a, const Task* b) { return a->id < b->id; });
  EXPECT_EQ(draw_tasks(pointers(all), 15, DrawKind::kUniform, draw_seed(3, "apt", 2)), legacy);
  // Asking for more than there are, or for all, gives all.
  EXPECT_EQ(draw_tasks(pointers(all), 0, DrawKind::kStratified, 1).size(), all.size());
  EXPECT_EQ(draw_tasks(pointers(all), 1000, DrawKind::kStratified, 1).size(), all.size());
  EXPECT_THROW(draw_kind_from_string("random"), Error);
}

TEST(Draw, StrataOfEachLevel) {
  Task l3 = atomic(1, "a_platform_0", "x_1", 3);
  nlohmann::json parts = nlohmann::json::array();
  parts.push_back({{"item", "x_1"}, {"source", "a_platform_0"}, {"platform", "b_platform_0"}});
  parts.push_back({{"item", "y_2"}, {"source", "c_platform_0"}, {"platform", "a_platform_0"}});
  l3.goal = nlohmann::json::object();
  l3.goal["sequence"] = parts;
  EXPECT_EQ(stratum_of(l3).primary, "a_platform_0");
  EXPECT_EQ(stratum_of(l3).secondary, "a_platform_0+b_platform_0+c_platform_0");
  Task l4 = atomic(2, "", "", 4);
  l4.type = "outcome:arrange_on";
  l4.template_id = "arrange_on/3";
  EXPECT_EQ(stratum_of(l4).primary, "arrange_on");
  EXPECT_EQ(stratum_of(l4).secondary, "arrange_on/3");
  EXPECT_EQ(stratum_of(atomic(3, "s_platform_1", "frl_apartment_cup_01_12")).secondary, "frl_apartment_cup_01");
}

class SuiteFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mtg_suite_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    scene::DatasetFingerprint f;
    f.files["configs/scenes/apt.scene_instance.json"] = "0123456789abcdef";
    dataset_["apt"] = f;
    SuiteDraw draw;
    draw.per_level = 5;
    draw.seed = 11;
    draw.levels = {2};
    all_ = lopsided();
    suite_ = draw_suite("unit-suite", all_, draw, {{"task_format", kGeneratorVersion}, {"config_hash", "abc"}}, dataset_);
    file_ = dir_ / "unit.json";
    write_suite(file_, suite_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string text() const {
    std::ifstream in(file_, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  void write_text(const std::string& t) const { std::ofstream(file_, std::ios::binary | std::ios::trunc) << t; }
  std::string error_of_reading() const {
    try {
      (void)read_suite(file_);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_, file_;
  std::vector<Task> all_;
  std::map<std::string, scene::DatasetFingerprint> dataset_;
  Suite suite_;
};

TEST_F(SuiteFile, ReadsBackWhatWasWrittenAndIsItsOwnIdentity) {
  const Suite back = read_suite(file_);
  EXPECT_EQ(back.id(), suite_.id());
  EXPECT_EQ(back.id().rfind("unit-suite@", 0), 0u) << back.id();
  EXPECT_EQ(back.digest.size(), 64u);
  ASSERT_EQ(back.tasks.size(), 5u);
  for (std::size_t i = 0; i < back.tasks.size(); ++i) EXPECT_EQ(task_to_json(back.tasks[i]), task_to_json(suite_.tasks[i]));
  EXPECT_EQ(back.draw.per_level, 5);
  EXPECT_EQ(back.draw.scenes, (std::set<std::string>{"apt"}));
  EXPECT_EQ(back.license, kReplicaCadLicense);
  // Drawing again from the same set with the same seed is the same suite, byte for byte.
  const std::string first = text();
  Suite again = draw_suite("unit-suite", all_, suite_.draw, suite_.generator, dataset_);
  write_suite(file_, again);
  EXPECT_EQ(text(), first);
  // A task set's readers take a suite: the run's tasks come from it.
  EXPECT_TRUE(is_suite_file(file_));
  EXPECT_EQ(read_tasks(file_).size(), 5u);
  EXPECT_EQ(read_task_set_meta(file_, "config_hash").value_or(""), "abc");
  EXPECT_EQ(read_task_set_meta(file_, "suite_id").value_or(""), suite_.id());
  EXPECT_EQ(read_dataset_fingerprints(file_).at("apt").digest(), dataset_.at("apt").digest());
  EXPECT_EQ(task_db_stats(file_)["total"].get<int>(), 5);
}

TEST_F(SuiteFile, AnEditedTruncatedOrForeignFileIsRefusedInOneLine) {
  const std::string good = text();
  auto expect_refused = [&](const std::string& damaged, const std::string& words) {
    write_text(damaged);
    const std::string e = error_of_reading();
    EXPECT_NE(e.find(file_.string()), std::string::npos) << e;
    EXPECT_NE(e.find(words), std::string::npos) << "expected '" << words << "' in: " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  };
  // A task's text edited: the content no longer hashes to the digest.
  std::string edited = good;
  const auto at = edited.find("move ");
  ASSERT_NE(at, std::string::npos);
  edited.replace(at, 5, "MOVE ");
  expect_refused(edited, "does not match its digest");
  // Cut short.
  expect_refused(good.substr(0, good.size() / 2), "cut short");
  // Another digest written in (and the id with it).
  std::string other = good;
  const auto d = other.find(suite_.digest);
  other.replace(d, 4, "ffff");
  expect_refused(other, "does not match its digest");
  // A format this version does not know.
  std::string future = good;
  future.replace(future.find("mtg-suite/1"), 11, "mtg-suite/9");
  expect_refused(future, "not one this mtg reads");
  // Not a suite at all.
  expect_refused("[1, 2, 3]", "not a suite");
  // The id must be the name and digest: a renamed suite is another suite.
  std::string renamed = good;
  renamed.replace(renamed.find("\"id\": \"unit-suite@"), 18, "\"id\": \"other-name@");
  expect_refused(renamed, "is not its name and digest");
}

TEST_F(SuiteFile, NamesAreChecked) {
  Suite s = suite_;
  s.name = "../x";
  EXPECT_THROW(write_suite(dir_ / "bad.json", s), Error);
  SuiteDraw draw = suite_.draw;
  draw.scenes = {"elsewhere"};
  EXPECT_THROW((void)draw_suite("x", all_, draw, {}, dataset_), Error);
}

// Runs number items as the tasks were planned: stable from mtg-tasks/4 on, the release's
// per-state numbering for older formats and for a set that does not say (a later version keeps
// its numbering too).
TEST(TaskFormat, RunsNumberItemsAsTheTasksWerePlanned) {
  EXPECT_EQ(numbering_of_format(kGeneratorVersion), episode::Numbering::kStable);
  EXPECT_EQ(numbering_of_format("mtg-tasks/4"), episode::Numbering::kStable);
  EXPECT_EQ(numbering_of_format("mtg-tasks/12"), episode::Numbering::kStable);
  for (const char* old : {"mtg-tasks/1", "mtg-tasks/2", "mtg-tasks/3", "", "unknown", "mtg-tasks/", "mtg-tasks/4x"}) {
    EXPECT_EQ(numbering_of_format(old), episode::Numbering::kPerState) << old;
  }
}

// Runs build their graphs as the tasks were planned: platforms inside their furniture are the
// part reached through the opening from mtg-tasks/5 on, whole surfaces before (the frozen suites'
// goals name cells of a TV stand's whole floor).
TEST(TaskFormat, RunsBuildPlatformsAsTheTasksWerePlanned) {
  EXPECT_EQ(platform_rules_of_format(kGeneratorVersion), graph::PlatformRules::kReachedAndSeen);
  EXPECT_EQ(platform_rules_of_format("mtg-tasks/5"), graph::PlatformRules::kReachedAndSeen);
  EXPECT_EQ(platform_rules_of_format("mtg-tasks/10"), graph::PlatformRules::kReachedAndSeen);
  for (const char* old : {"mtg-tasks/1", "mtg-tasks/2", "mtg-tasks/4", "", "mtg-tasks/5 ", "mtg-tasks/-5"}) {
    EXPECT_EQ(platform_rules_of_format(old), graph::PlatformRules::kWholeSurface) << old;
  }
  EXPECT_EQ(graph::platform_rules_from_string(graph::to_string(graph::PlatformRules::kWholeSurface), "x"),
            graph::PlatformRules::kWholeSurface);
  EXPECT_EQ(graph::platform_rules_from_string(graph::to_string(graph::PlatformRules::kReachedAndSeen), "x"),
            graph::PlatformRules::kReachedAndSeen);
  EXPECT_THROW((void)graph::platform_rules_from_string("open", "plan.json: platform_rules"), Error);
}

}  // namespace
}  // namespace mtg::tasks
