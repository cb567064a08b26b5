// Task generation on small fixture scenes: the goals found, their oracle plans, levels,
// determinism, storage and bad input.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/episode/world_state.h"
#include "core/tasks/atomic.h"
#include "core/tasks/generator.h"
#include "core/tasks/job.h"
#include "core/tasks/lookalike_aid.h"
#include "core/tasks/outcome.h"
#include "core/tasks/sequential.h"
#include "core/tasks/task_db.h"
#include "core/tasks/validate.h"
#include "core/store/sqlite.h"
#include "core/util/error.h"
#include "tests/support/graph_fixtures.h"

namespace mtg::tasks {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

TaskOptions small_options() {
  TaskOptions o;
  o.level3_count = 50;
  return o;
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(AtomicTasks, MovingABoxToTheEmptyTableGivesTheSurfaceAndItsNineParts) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const auto& g = b.graph;
  const auto tasks = enumerate_atomic(g, episode::initial_state(g), small_options());
  const auto box1 = g.find_object("box_1");
  const auto empty = g.navigable[1];
  std::multiset<std::string> types;
  for (const auto& t : tasks) {
    if (t.goal.item == box1 && t.goal.platform == empty) types.insert(episode::to_string(t.goal.type));
  }
  EXPECT_EQ(types.count("surface"), 1u);
  EXPECT_EQ(types.count("surface_part"), 9u);
  EXPECT_EQ(types.size(), 10u);
}

TEST(AtomicTasks, BetweenAndDirectionGoalsOnTheOccupiedTable) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const auto& g = b.graph;
  const auto tasks = enumerate_atomic(g, episode::initial_state(g), small_options());
  const auto box1 = g.find_object("box_1"), box2 = g.find_object("box_2"), box3 = g.find_object("box_3");
  bool between_2_3 = false, around_2 = false;
  std::set<int> directions_of_3;
  for (const auto& t : tasks) {
    if (t.goal.item != box1 || t.goal.platform != g.navigable[0]) continue;
    between_2_3 |= t.goal.type == episode::GoalType::kBetween && t.goal.anchor == box2 && t.goal.anchor2 == box3;
    around_2 |= t.goal.type == episode::GoalType::kAround && t.goal.anchor == box2;
    if (t.goal.type == episode::GoalType::kDirection && t.goal.anchor == box3) directions_of_3.insert(t.goal.direction);
    EXPECT_NE(t.goal.type, episode::GoalType::kSurface);  // not onto its own platform
  }
  EXPECT_TRUE(between_2_3);  // the 0.2 m gap between the other two boxes takes it
  EXPECT_TRUE(around_2);
  // Free all around box_3 once box_1 is picked, but box_1 already stands left of box_3: seen from
  // the left, right or front side of the table (where the robot can stand too) that is box_3's
  // rear, front or right. Putting box_1 back where it is would meet those goals, so only the
  // four corners are asked for.
  EXPECT_EQ(directions_of_3, (std::set<int>{1, 3, 5, 7}));
}

TEST(AtomicTasks, EveryOraclePlanSucceedsUnderTheEpisodeRules) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const auto result = generate_tasks(b.scene, b.graph, small_options());
  ASSERT_GT(result.set.tasks.size(), 100u);
  int ok = 0;
  for (const Task& t : result.set.tasks) {
    const PlayResult r = play_task(b.graph, t, small_options());
    EXPECT_TRUE(r.success) << t.id << " " << t.text << ": " << r.failure;
    ok += r.success ? 1 : 0;
  }
  EXPECT_EQ(ok, static_cast<int>(result.set.tasks.size()));
}

TEST(TaskLevels, IdenticalObjectsMakeATaskLevelTwo) {
  testing::FixtureDataset fx;
  testing::add_table(fx, "table");
  fx.add_object_config("toy_cup", fx.add_box_mesh("cup", {0.08, 0.1, 0.08}));
  fx.add_object_config("toy_plate", fx.add_box_mesh("plate", {0.2, 0.02, 0.2}));
  fx.add_scene("s", {{"object_instances",
                      {testing::FixtureDataset::instance("toy_table", {0, 0, 0}),
                       testing::FixtureDataset::instance("toy_cup", testing::hab(-0.3, 0, 0.74)),
                       testing::FixtureDataset::instance("toy_cup", testing::hab(0.3, 0, 0.74)),
                       testing::FixtureDataset::instance("toy_table", testing::hab(3, 0, 0)),
                       testing::FixtureDataset::instance("toy_plate", testing::hab(3, 0, 0.74))}}});
  const auto b = testing::build_fixture_scene(fx, "s");
  TaskOptions o = small_options();
  o.levels = {1, 2};
  const auto result = generate_tasks(b.scene, b.graph, o);
  int l1 = 0, l2 = 0;
  for (const Task& t : result.set.tasks) {
    const bool cup_involved = t.item.rfind("cup", 0) == 0 ||
                              std::any_of(t.anchors.begin(), t.anchors.end(), [](const std::string& a) { return a.rfind("cup", 0) == 0; });
    // Both cups stand on table_0: a cup as item (from there) or as anchor (there) is ambiguous.
    EXPECT_EQ(t.level, cup_involved ? 2 : 1) << t.text;
    (t.level == 1 ? l1 : l2) += 1;
  }
  EXPECT_GT(l1, 0);
  EXPECT_GT(l2, 0);
}

// The look-alike aids (lookalike_aid.h): words alone keep the text and drop the close-ups'
// sentence; images alone name each look-alike by its close-up (the one from its own platform where
// two share their words, a capital where a sentence starts) and refuse a run without images.
TEST(LookalikeAid, EachAidSaysWhatItGives) {
  auto id = [](const std::string& object, const std::string& platform, const std::string& phrase) {
    Identification i;
    i.role = "object";
    i.object = object;
    i.platform = platform;
    i.reference.relation = Relation::kFromLeft;
    i.reference.noun = "book";
    i.reference.rank = 1;
    i.phrase = phrase;
    return i;
  };
  const std::vector<Identification> ids = {id("book_2", "shelf_3", "the leftmost book"),
                                           id("book_1", "shelf_1", "the leftmost book")};
  const std::string text = "The leftmost book from shelf_1 and the leftmost book from shelf_3 go on table_0.";
  const TaskWords both = task_words("t", text, ids, episode::LookalikeAid::kBoth, true);
  EXPECT_EQ(both.text, text);
  EXPECT_THAT(both.hint, ::testing::HasSubstr("Close-up images show them"));
  const TaskWords words = task_words("t", text, ids, episode::LookalikeAid::kWords, true);
  EXPECT_EQ(words.text, text);
  EXPECT_THAT(words.hint, ::testing::HasSubstr("the leftmost book (on shelf_3)"));
  EXPECT_THAT(words.hint, ::testing::Not(::testing::HasSubstr("lose-up")));
  const TaskWords image = task_words("t", text, ids, episode::LookalikeAid::kImage, true);
  EXPECT_EQ(image.text, "The book in close-up 2 from shelf_1 and the book in close-up 1 from shelf_3 go on table_0.");
  EXPECT_EQ(image.hint,
            "Some objects of this task have look-alikes; the task names each by the close-up image that shows it: "
            "close-up 1 on shelf_3 and close-up 2 on shelf_1. A close-up shows the object where it stands, seen "
            "from where you arrive at its platform, every other object faded.");
  EXPECT_THAT(image.hint, ::testing::Not(::testing::HasSubstr("leftmost")));
  EXPECT_THROW(task_words("t", text, ids, episode::LookalikeAid::kImage, false), Error);
  EXPECT_THROW(task_words("t", "Move the book.", ids, episode::LookalikeAid::kImage, true), Error);
  EXPECT_EQ(task_words("t", "Move the cup.", {}, episode::LookalikeAid::kImage, true).text, "Move the cup.");
  for (const auto aid : {episode::LookalikeAid::kBoth, episode::LookalikeAid::kImage, episode::LookalikeAid::kWords}) {
    EXPECT_EQ(episode::lookalike_aid_from_string(episode::to_string(aid), "aid"), aid);
  }
  EXPECT_THROW(episode::lookalike_aid_from_string("pictures", "aid"), Error);
}

TEST(TaskGeneration, SameSeedSameBytesOtherSeedOtherChoices) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const fs::path dir = fx.root();
  auto write = [&](std::uint64_t seed, const std::string& tag) {
    TaskOptions o = small_options();
    o.seed = seed;
    const auto r = generate_tasks(b.scene, b.graph, o);
    write_task_db(dir / (tag + ".sqlite"), {r.set}, r.votes, o, dir / (tag + ".jsonl"));
  };
  write(7, "a");
  write(7, "b");
  write(8, "c");
  EXPECT_EQ(read_file(dir / "a.jsonl"), read_file(dir / "b.jsonl"));
  EXPECT_EQ(read_file(dir / "a.sqlite"), read_file(dir / "b.sqlite"));
  EXPECT_NE(read_file(dir / "a.jsonl"), read_file(dir / "c.jsonl"));
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().string().find(".partial"), std::string::npos) << e.path();  // none left behind
  }
}

// Threads share Levels 1-3 (items, chains); the bytes must not tell how many there were. Four
// threads on the fixture's few items, with enough chains that duplicates are drawn again.
TEST(TaskGeneration, AnyNumberOfThreadsWritesTheSameBytes) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const fs::path dir = fx.root();
  TaskOptions o = small_options();
  o.level3_count = 200;
  for (const int jobs : {1, 4}) {
    const auto r = generate_tasks(b.scene, b.graph, o, {}, {}, jobs);
    const std::string tag = "jobs" + std::to_string(jobs);
    write_task_db(dir / (tag + ".sqlite"), {r.set}, r.votes, o, dir / (tag + ".jsonl"));
  }
  EXPECT_EQ(read_file(dir / "jobs1.jsonl"), read_file(dir / "jobs4.jsonl"));
  EXPECT_EQ(read_file(dir / "jobs1.sqlite"), read_file(dir / "jobs4.sqlite"));
}

// Scenes side by side: the files and the order scenes are reported in are those of one thread.
TEST(TaskGeneration, ScenesSideBySideWriteTheBytesOfOneThread) {
  testing::FixtureDataset fx;
  testing::two_tables(fx);
  testing::render_room(fx);
  const std::vector<std::string> scenes = {"two_tables", "render_room"};
  for (const int jobs : {1, 4}) {  // four threads run the two scenes side by side
    GenerationJob job;
    job.scenes = scenes;
    job.data_dir = fx.root().string();
    job.profile = "none";
    job.options = small_options();
    job.out = (fx.root() / ("jobs" + std::to_string(jobs) + ".sqlite")).string();
    job.jsonl = (fx.root() / ("jobs" + std::to_string(jobs) + ".jsonl")).string();
    job.jobs = jobs;
    std::vector<std::string> reported;
    run_generation(job, [&](const SceneReport& r) { reported.push_back(r.scene); });
    EXPECT_EQ(reported, scenes) << "jobs " << jobs;
  }
  EXPECT_EQ(read_file(fx.root() / "jobs1.jsonl"), read_file(fx.root() / "jobs4.jsonl"));
  EXPECT_EQ(read_file(fx.root() / "jobs1.sqlite"), read_file(fx.root() / "jobs4.sqlite"));
  for (const auto& e : fs::directory_iterator(fx.root())) {
    EXPECT_EQ(e.path().string().find(".partial"), std::string::npos) << e.path();  // none left behind
  }
}

// `mtg tasks` streams a scene's tasks into the database in batches, and chunks a later scene's
// while an earlier one is still being written: the bytes must be those of writing each whole set.
TEST(TaskGeneration, HowTasksAreBatchedOrHeldDoesNotChangeTheBytes) {
  testing::FixtureDataset fx;
  const auto a = testing::two_tables(fx);
  const auto b = testing::render_room(fx);
  TaskOptions o = small_options();
  o.level3_count = 200;
  const auto ra = generate_tasks(a.scene, a.graph, o);
  const auto rb = generate_tasks(b.scene, b.graph, o);
  ASSERT_GT(ra.set.tasks.size(), 3u * 64u);  // several chunks, and a part chunk at the end
  std::vector<Vote> votes = ra.votes;
  votes.insert(votes.end(), rb.votes.begin(), rb.votes.end());
  const fs::path dir = fx.root();
  write_task_db(dir / "whole.sqlite", {ra.set, rb.set}, votes, o, dir / "whole.jsonl");

  // Batches of odd sizes cut across chunks, for both scenes at once.
  const auto batches = [](const std::vector<Task>& tasks) {
    std::vector<std::vector<Task>> out;
    const std::size_t sizes[] = {1, 63, 70, 129};
    for (std::size_t at = 0, k = 0; at < tasks.size(); ++k) {
      const std::size_t n = std::min(tasks.size() - at, sizes[k % 4]);
      out.emplace_back(tasks.begin() + static_cast<std::ptrdiff_t>(at), tasks.begin() + static_cast<std::ptrdiff_t>(at + n));
      at += n;
    }
    return out;
  };
  const auto without_tasks = [](TaskSet set) {
    set.tasks.clear();
    return set;
  };
  {
    TaskDbWriter writer(dir / "streamed.sqlite", o, dir / "streamed.jsonl", 3);
    std::vector<Task> rest_a, rest_b;
    std::vector<TaskChunk> waiting;  // the second scene's, made while the first is written
    const auto first = batches(ra.set.tasks), second = batches(rb.set.tasks);
    for (std::size_t k = 0; k < std::max(first.size(), second.size()); ++k) {
      if (k < first.size()) {
        rest_a.insert(rest_a.end(), first[k].begin(), first[k].end());
        writer.store(writer.make_chunks(rest_a, false));
      }
      if (k < second.size()) {
        rest_b.insert(rest_b.end(), second[k].begin(), second[k].end());
        for (TaskChunk& c : writer.make_chunks(rest_b, false)) waiting.push_back(std::move(c));
      }
    }
    writer.store(writer.make_chunks(rest_a, true));
    writer.end_scene(without_tasks(ra.set));
    writer.store(std::move(waiting));
    writer.store(writer.make_chunks(rest_b, true));
    writer.end_scene(without_tasks(rb.set));
    writer.finish(votes);
  }
  EXPECT_EQ(read_file(dir / "whole.jsonl"), read_file(dir / "streamed.jsonl"));
  EXPECT_EQ(read_file(dir / "whole.sqlite"), read_file(dir / "streamed.sqlite"));
}

// Level 3 asks for part of the set (one goal; goals about one object): it must get exactly
// that part of the whole enumeration, with the same plans.
TEST(AtomicTasks, APartialEnumerationHoldsExactlyItsPartOfTheWhole) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const TaskOptions options = small_options();
  const episode::WorldState s = episode::initial_state(b.graph);
  const auto all = enumerate_atomic(b.graph, s, options);
  ASSERT_FALSE(all.empty());
  auto plan_of = [](const std::vector<AtomicTask>& tasks) {
    std::vector<std::string> out;
    for (const auto& t : tasks) {
      std::string line = t.key;
      for (const auto& k : t.oracle) line += " " + k;
      out.push_back(line);
    }
    return out;
  };
  int anchored = 0;
  for (const AtomicTask& t : all) {
    const auto one = enumerate_atomic(b.graph, s, options, {{t.goal.item}, {t.goal.platform}, t.key, {}});
    EXPECT_EQ(plan_of(one), plan_of({t}));
    for (const graph::ObjectId anchor : t.goal.anchors()) {
      ++anchored;
      std::vector<AtomicTask> expected;
      for (const AtomicTask& u : all) {
        const auto a = u.goal.anchors();
        if (u.goal.item == t.goal.item && u.goal.platform == t.goal.platform &&
            std::find(a.begin(), a.end(), anchor) != a.end()) {
          expected.push_back(u);
        }
      }
      const auto about = enumerate_atomic(b.graph, s, options, {{t.goal.item}, {t.goal.platform}, "", anchor});
      EXPECT_EQ(plan_of(about), plan_of(expected)) << "anchor " << anchor;
    }
  }
  EXPECT_GT(anchored, 0) << "the fixture has goals relative to objects";
}

// Generation keeps placement geometry in a memo (placement.h): a cold memo, a warm one and none
// must give the same bits, down to the placed positions and margins.
TEST(AtomicTasks, ThePlacementMemoChangesNoBit) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const TaskOptions options = small_options();
  const episode::WorldState s = episode::initial_state(b.graph);
  auto bits_of = [](const std::vector<AtomicTask>& tasks) {
    std::vector<std::string> out;
    for (const AtomicTask& t : tasks) {
      std::string line = t.key;
      for (const auto& k : t.oracle) line += " " + k;
      for (const double v : {t.place_xy.x(), t.place_xy.y(), t.placed_at.x(), t.placed_at.y(), t.placed_at.z(), t.margin}) {
        line.append(reinterpret_cast<const char*>(&v), sizeof v);
      }
      out.push_back(line);
    }
    return out;
  };
  const auto plain = enumerate_atomic(b.graph, s, options);
  episode::PlacementMemo memo(/*keep_whole_results=*/true);
  const auto cold = enumerate_atomic(b.graph, s, options, {}, nullptr, 2, &memo);
  const std::size_t kept = memo.feasible.size();
  const auto warm = enumerate_atomic(b.graph, s, options, {}, nullptr, 1, &memo);
  ASSERT_FALSE(plain.empty());
  EXPECT_GT(memo.tables->insets.size(), 0u);
  EXPECT_GT(memo.tables->interiors.size(), 0u);
  EXPECT_GT(kept, 0u);
  EXPECT_EQ(memo.feasible.size(), kept) << "the second enumeration found everything in the memo";
  EXPECT_EQ(bits_of(cold), bits_of(plain));
  EXPECT_EQ(bits_of(warm), bits_of(plain));

  // Level 3 chains re-plan in changed states: with or without a memo, the same chains.
  auto chains = [&](episode::PlacementMemo* m) {
    std::vector<std::string> out;
    std::vector<std::string> warnings;
    DropCounts dropped;
    generate_sequences(
        b.graph, s, plain, 40, options, warnings, dropped, 2,
        [&](Sequence seq) {
          for (const auto& line : bits_of(seq.parts)) out.push_back(line);
          out.push_back("|");
        },
        m);
    return out;
  };
  episode::PlacementMemo chain_memo;
  EXPECT_EQ(chains(&chain_memo), chains(nullptr));
}

TEST(TaskGeneration, NoDuplicateGoals) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const auto r = generate_tasks(b.scene, b.graph, small_options());
  std::set<std::string> goals;
  for (const Task& t : r.set.tasks) {
    EXPECT_TRUE(goals.insert(std::to_string(t.level >= 3 ? t.level : 0) + t.goal.dump()).second) << t.id;
  }
}

TEST(TaskGeneration, StatsCountLevelsTypesAndScenes) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const auto r = generate_tasks(b.scene, b.graph, small_options());
  const fs::path db = fx.root() / "t.sqlite";
  write_task_db(db, {r.set}, r.votes, small_options());
  const auto stats = task_db_stats(db);
  std::int64_t sum = 0;
  for (const char* l : {"1", "2", "3", "4"}) sum += stats["levels"][l].get<std::int64_t>();
  EXPECT_EQ(sum, static_cast<std::int64_t>(r.set.tasks.size()));
  EXPECT_EQ(stats["scenes"]["two_tables"]["total"], sum);
  EXPECT_GT(stats["levels"]["3"].get<int>(), 0);
  EXPECT_EQ(read_tasks(db).size(), r.set.tasks.size());
  EXPECT_EQ(read_tasks(db, {3}).size(), static_cast<std::size_t>(stats["levels"]["3"].get<int>()));
  // Breadth beside the counts: the pickable items on navigable platforms, and which the tasks use,
  // counted again here from the tasks themselves.
  const nlohmann::json& c = stats["coverage"]["two_tables"];
  std::set<std::string> pickable, in_1_2, in_2;
  const episode::WorldState s = episode::initial_state(b.graph);
  for (const graph::PlatformId p : b.graph.navigable) {
    for (const graph::ObjectId o : episode::pickable_on(b.graph, s, p)) pickable.insert(b.graph.objects[o].name);
  }
  for (const Task& t : r.set.tasks) {
    if (t.level <= 2) in_1_2.insert(t.item);
    if (t.level == 2) in_2.insert(t.item);
  }
  EXPECT_EQ(c["pickable"], pickable.size());
  EXPECT_EQ(c["in_levels_1_2"], in_1_2.size());
  EXPECT_GE(c["in_any_task"].get<std::size_t>(), in_1_2.size());
  EXPECT_LE(c["seen_with_lookalike_in_level_2"].get<std::size_t>(), in_2.size());
  EXPECT_EQ(c["not_in_levels_1_2"].size(), pickable.size() - in_1_2.size());
  EXPECT_GT(c["level_2_top3_share"].get<double>(), 0.0);
  EXPECT_LE(c["level_2_top3_share"].get<double>(), 1.0);
}

// A database's chunks hold each task written straight from its fields: the text of its JSON.
TEST(TaskGeneration, TasksAreWrittenAsTheirJsonPrints) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  std::vector<Task> tasks = generate_tasks(b.scene, b.graph, small_options()).set.tasks;
  Task odd;  // every optional part, text to escape, an unbounded margin
  odd.id = "s/L2/000001";
  odd.text = "put the \"red\" cup\tnext to the caf\xc3\xa9 sign";
  odd.anchors = {"a", "b"};
  odd.goal = {{"atomic", {{"type", "between"}, {"x", 0.1}}}};
  odd.identify.push_back({1, "anchor", "cup_2", "table", {Relation::kNextTo, "cup", "plate", 0}, "the cup next to the plate"});
  odd.identify.push_back({0, "item", "book_1", "shelf", {Relation::kFromLeft, "book", "", 2}, "the second book from the left"});
  odd.placements.push_back({0, "cup_2", "table", {1.0, -0.5, 1e-7}, std::numeric_limits<double>::infinity()});
  odd.placements.push_back({1, "book_1", "shelf", {0.1, 0.2, 0.3}, 0.0123});
  tasks.push_back(odd);
  std::set<int> levels;
  for (const Task& t : tasks) {
    std::string line = "[";
    append_task_json(line, t);
    EXPECT_EQ(line, "[" + task_to_json(t).dump()) << t.id;
    levels.insert(t.level);
  }
  EXPECT_EQ(levels, (std::set<int>{1, 2, 3, 4})) << "every level's fields were compared";
}

// A stored task is input: limits that would make planning or prompts take gigabytes are refused
// with one line naming the task.
TEST(TaskGeneration, AStoredTaskBeyondTheLimitsIsRefusedByName) {
  Task t;
  t.id = "s/L1/000007";
  t.scene = "s";
  t.level = 1;
  t.type = "surface";
  t.text = "Put the cup on the table.";
  t.goal = {{"atomic", {{"type", "surface"}}}};
  t.step_limit = 15;
  EXPECT_EQ(task_from_json(task_to_json(t)).step_limit, 15);
  Task huge = t;
  huge.step_limit = 100000000;
  EXPECT_THAT([&] { task_from_json(task_to_json(huge)); },
              ::testing::ThrowsMessage<Error>(HasSubstr("task s/L1/000007: step_limit 100000000 is not in 1..1000")));
  Task wordy = t;
  wordy.text = std::string(4 << 20, 'a');
  EXPECT_THAT([&] { task_from_json(task_to_json(wordy)); },
              ::testing::ThrowsMessage<Error>(HasSubstr("task s/L1/000007: its text has 4194304 bytes")));
  Task odd = t;
  odd.level = 9;
  EXPECT_THROW(task_from_json(task_to_json(odd)), Error);
}

// The database keeps every field of every task (compressed 64 to a chunk), gives them back in id
// order, says which task a damaged chunk holds, and the stock sqlite3 shell reads them too.
TEST(TaskGeneration, TheDatabaseGivesBackEveryTaskAndTheShellReadsItToo) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  TaskOptions o = small_options();
  o.level3_count = 150;  // several chunks
  const auto r = generate_tasks(b.scene, b.graph, o);
  const fs::path db = fx.root() / "t.sqlite";
  write_task_db(db, {r.set}, r.votes, o);
  std::vector<Task> written = r.set.tasks;
  std::sort(written.begin(), written.end(), [](const Task& x, const Task& y) { return x.id < y.id; });
  const std::vector<Task> read = read_tasks(db);
  ASSERT_EQ(read.size(), written.size());
  ASSERT_GT(read.size(), 128u);
  for (std::size_t i = 0; i < read.size(); ++i) {
    ASSERT_EQ(task_to_json(read[i]).dump(), task_to_json(written[i]).dump()) << written[i].id;
  }

  // The shell: the view's JSON is the task's.
  const Task& last = written.back();
  const std::string query = "sqlite3 '" + db.string() + "' \"SELECT task FROM task_json WHERE id = '" + last.id + "'\"";
  if (FILE* pipe = popen(query.c_str(), "r"); pipe != nullptr) {
    std::string out;
    char buf[4096];
    while (const std::size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
    ASSERT_EQ(pclose(pipe), 0) << "sqlite3 (scripts/install-deps installs it) failed: " << query;
    EXPECT_EQ(nlohmann::json::parse(out), task_to_json(last));
  }

  // A damaged chunk: one line naming the file and the task.
  {
    store::Database rw(db, store::Database::Mode::kReadWrite);
    rw.exec("UPDATE task_chunks SET body = x'789c0000' WHERE chunk = (SELECT chunk FROM tasks WHERE id = '" + last.id +
            "')");
  }
  EXPECT_THAT([&] { read_tasks(db); },
              ::testing::ThrowsMessage<Error>(AllOf(HasSubstr(db.string()), HasSubstr("damaged stream"))));
  EXPECT_NO_THROW(read_tasks(db, {1}));  // the last chunk holds Level 3 tasks only
}

TEST(TaskGeneration, BadInputIsRejectedWithTheNameOfWhatIsWrong) {
  EXPECT_THAT([] { parse_levels("1,5"); }, ::testing::ThrowsMessage<Error>(HasSubstr("unknown level '5'")));
  testing::FixtureDataset fx;
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.1, 0.1, 0.1}));
  fx.add_scene("bare", {{"object_instances", {testing::FixtureDataset::instance("toy_box", {0, 0, 0})}}});
  const auto bare = testing::build_fixture_scene(fx, "bare");
  EXPECT_THAT([&] { generate_tasks(bare.scene, bare.graph, small_options()); },
              ::testing::ThrowsMessage<Error>(HasSubstr("has no navigable platform")));
  fx.write_text("bad_templates.json",
                R"({"templates": [{"id": "x-001", "family": "pair", "kind": "pair", "text": "Put the {object} by the {vase}."}]})");
  EXPECT_THAT([&] { load_templates((fx.root() / "bad_templates.json").string()); },
              ::testing::ThrowsMessage<Error>(HasSubstr("unknown placeholder {vase}")));
  fx.write_text("bad_votes.jsonl", "{\"task_id\": \"a\", \"voter\": \"v\", \"verdict\": \"maybe\"}\n");
  EXPECT_THAT([&] { load_votes((fx.root() / "bad_votes.jsonl").string()); },
              ::testing::ThrowsMessage<Error>(HasSubstr("bad_votes.jsonl:1: unknown verdict 'maybe'")));
}

TEST(TaskGeneration, TheBuiltInTemplateLibraryHasEveryKindInSeveralPhrasings) {
  const auto templates = load_templates("builtin");
  EXPECT_GE(templates.size(), 200u);
  std::set<std::string> families;
  std::map<std::string, int> phrasings;
  for (const auto& t : templates) {
    families.insert(t.family);
    phrasings[to_string(t.kind)] += 1;
  }
  EXPECT_EQ(families, (std::set<std::string>{"arrange", "clear", "count", "gather", "pair", "set_up", "sort", "store",
                                              "swap"}));
  EXPECT_EQ(phrasings.size(), 31u);
  for (const auto& [kind, n] : phrasings) EXPECT_GE(n, 5) << kind;
}

TEST(TaskGeneration, RecordedVotesCanVetoAnOutcomeTask) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  TaskOptions o = small_options();
  o.levels = {4};
  const auto first = generate_tasks(b.scene, b.graph, o);
  ASSERT_FALSE(first.set.tasks.empty());
  const std::string victim = first.set.tasks.front().id;
  const std::vector<Vote> votes = {{victim, "model-a", kNotFeasible}, {victim, "model-b", kNotFeasible}};
  const auto second = generate_tasks(b.scene, b.graph, o, votes);
  EXPECT_EQ(second.set.tasks.size() + 1, first.set.tasks.size());
  for (const Task& t : second.set.tasks) EXPECT_NE(t.id, victim);
  // Ids of the others do not move when one is vetoed.
  EXPECT_EQ(second.set.tasks.front().id, first.set.tasks[1].id);
}

}  // namespace
}  // namespace mtg::tasks
