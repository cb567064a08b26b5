// References to look-alikes (referring.h, identify.h) on small fixture scenes: ordinals counted
// from the arrival side, stacking relations, the states a reference must hold in, and the tasks
// that are dropped because no reference tells their objects apart.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/episode/rules.h"
#include "core/render/visibility.h"
#include "core/tasks/generator.h"
#include "core/tasks/atomic.h"
#include "core/tasks/identify.h"
#include "core/tasks/reference_memo.h"
#include "core/tasks/referring.h"
#include "core/tasks/validate.h"
#include "core/util/error.h"
#include "tests/support/graph_fixtures.h"

namespace mtg::tasks {
namespace {

using ::testing::HasSubstr;

std::optional<Reference> refer_to(const graph::SceneGraph& g, const episode::WorldState& s, const char* name) {
  const auto o = g.find_object(name);
  return refer(g, {&s}, o, episode::furniture_platform_of(g, s, o), Ambiguity::kCategory).reference;
}

// Three identical boxes in a row on table_0 (x = -0.3, 0, 0.3), the robot arriving at the rear
// side (looking along +y): box_1 is the leftmost.
TEST(References, IdenticalBoxesInARowAreCountedFromTheArrivalSide) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const auto& g = b.graph;
  ASSERT_EQ(g.platforms[g.navigable[0]].default_side, 0);
  const episode::WorldState s = episode::initial_state(g);
  EXPECT_EQ(refer_to(g, s, "box_1")->phrase(), "the leftmost box");
  EXPECT_EQ(refer_to(g, s, "box_2")->phrase(), "the second box from the left");
  EXPECT_EQ(refer_to(g, s, "box_3")->phrase(), "the rightmost box");
  // What a reader finds: exactly the object, and with box_1 in hand the leftmost is box_2.
  const auto table = g.navigable[0];
  const Reference leftmost = *refer_to(g, s, "box_1");
  EXPECT_EQ(resolve(g, s, table, leftmost, Ambiguity::kCategory), (std::vector<graph::ObjectId>{g.find_object("box_1")}));
  episode::WorldState held = s;
  episode::pick(g, held, g.find_object("box_1"));
  EXPECT_EQ(resolve(g, held, table, leftmost, Ambiguity::kCategory), (std::vector<graph::ObjectId>{g.find_object("box_2")}));
  // As JSON and back, as the task database stores it.
  EXPECT_EQ(Reference::from_json(leftmost.to_json()).phrase(), leftmost.phrase());
  const nlohmann::json bad_rank = {{"relation", "from_left"}, {"noun", "box"}, {"rank", 9}};
  EXPECT_THROW(Reference::from_json(bad_rank), mtg::Error);
}

// Level 2 texts name the instance; an anchor is named so it reads right both before the item
// is picked and while placing (the item comes from the same table here).
TEST(References, LevelTwoTextsPickOutTheGoalsInstances) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  TaskOptions o;
  o.levels = {1, 2};
  const GenerationResult r = generate_tasks(b.scene, b.graph, o);
  int checked = 0;
  for (const Task& t : r.set.tasks) {
    ASSERT_EQ(t.level, 2) << t.text;  // every box has look-alikes on table_0
    ASSERT_FALSE(t.identify.empty()) << t.text;
    for (const Identification& id : t.identify) EXPECT_THAT(t.text, HasSubstr(id.phrase)) << t.id;
    EXPECT_THAT(audit_task(b.graph, t, o), ::testing::IsEmpty()) << t.text;
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

// A box on a box: "the box on the box" and "the box under the box"; two thin pens whose centres
// stand 1.5 cm apart (touching) cannot be counted, so tasks about them are dropped and counted.
TEST(References, StacksAreNamedAndCrowdsAreDropped) {
  testing::FixtureDataset fx;
  testing::add_table(fx, "table");
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.1, 0.1, 0.1}));
  fx.add_object_config("toy_pen", fx.add_box_mesh("pen", {0.015, 0.02, 0.14}));
  fx.add_scene("s", {{"object_instances",
                      {testing::FixtureDataset::instance("toy_table", {0, 0, 0}),
                       testing::FixtureDataset::instance("toy_box", testing::hab(-0.3, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_box", testing::hab(-0.3, 0, 0.85)),
                       testing::FixtureDataset::instance("toy_pen", testing::hab(0.2, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_pen", testing::hab(0.215, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_table", testing::hab(3, 0, 0))}}});
  const auto b = testing::build_fixture_scene(fx, "s");
  const auto& g = b.graph;
  const episode::WorldState s = episode::initial_state(g);
  EXPECT_EQ(refer_to(g, s, "box_1")->phrase(), "the box under the box");
  EXPECT_EQ(refer_to(g, s, "box_2")->phrase(), "the box on the box");
  // The pens stand 1.5 cm apart: left-to-right counting cannot tell them apart.
  EXPECT_FALSE(refer_to(g, s, "pen_3").has_value());
  EXPECT_FALSE(refer_to(g, s, "pen_4").has_value());
  TaskOptions o;
  o.levels = {1, 2};
  const GenerationResult r = generate_tasks(b.scene, g, o);
  EXPECT_GT(r.set.dropped.by_reason.at("unidentifiable").at(2), 0);
  for (const Task& t : r.set.tasks) EXPECT_TRUE(t.item.rfind("pen", 0) != 0) << t.text;
}

// Look-alikes in two rows (a rack of jars) are counted along their row, and a stack of books from
// its top or bottom; both read back as JSON and resolve to exactly their object.
TEST(References, RowsAndStacksNameWhatOrdinalsCannot) {
  testing::FixtureDataset fx;
  testing::add_table(fx, "table");
  fx.add_object_config("toy_jar", fx.add_box_mesh("jar", {0.04, 0.04, 0.08}));
  fx.add_object_config("toy_book", fx.add_box_mesh("book", {0.1, 0.1, 0.1}));
  fx.add_scene("s", {{"object_instances",
                      {testing::FixtureDataset::instance("toy_table", {0, 0, 0}),
                       // two rows of two jars, the near row and the far row 8 cm apart, columns 8 cm apart
                       testing::FixtureDataset::instance("toy_jar", testing::hab(-0.3, -0.1, 0.75)),
                       testing::FixtureDataset::instance("toy_jar", testing::hab(-0.22, -0.1, 0.75)),
                       testing::FixtureDataset::instance("toy_jar", testing::hab(-0.3, -0.02, 0.75)),
                       testing::FixtureDataset::instance("toy_jar", testing::hab(-0.22, -0.02, 0.75)),
                       // three books in one stack
                       testing::FixtureDataset::instance("toy_book", testing::hab(0.25, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(0.25, 0, 0.85)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(0.25, 0, 0.95)),
                       testing::FixtureDataset::instance("toy_table", testing::hab(3, 0, 0))}}});
  const auto b = testing::build_fixture_scene(fx, "s");
  const auto& g = b.graph;
  const episode::WorldState s = episode::initial_state(g);
  const graph::PlatformId table = episode::furniture_platform_of(g, s, g.find_object("jar_1"));
  for (const char* name : {"jar_1", "jar_2", "jar_3", "jar_4", "book_5", "book_6", "book_7"}) {
    const auto r = refer_to(g, s, name);
    ASSERT_TRUE(r.has_value()) << name;
    EXPECT_EQ(resolve(g, s, table, *r, Ambiguity::kCategory), (std::vector<graph::ObjectId>{g.find_object(name)}))
        << name << ": " << r->phrase();
    EXPECT_EQ(Reference::from_json(r->to_json()).phrase(), r->phrase()) << name;
    const std::string phrase = r->phrase();
    if (std::string(name).rfind("jar", 0) == 0) {
      EXPECT_THAT(phrase, HasSubstr(" row")) << name;
    }
    if (std::string(name).rfind("book", 0) == 0) {
      EXPECT_THAT(phrase, ::testing::AnyOf(HasSubstr("of the stack"), HasSubstr("on the book"), HasSubstr("under the book")))
          << name;
    }
  }
  // The middle book is neither on top nor at the bottom: counted down the stack.
  EXPECT_EQ(refer_to(g, s, "book_6")->phrase(), "the second book from the top of the stack");
  const nlohmann::json bad_row = {{"relation", "nearest"}, {"noun", "jar"}, {"rank", 1}, {"row", "near"}};
  EXPECT_THROW(Reference::from_json(bad_row), mtg::Error);
}

// Counting past a pile: a person may count a stack once or book by book, so an ordinal is
// given only up to the first stack. A lone book on each side of a pile is the leftmost and the
// rightmost book; a lone book between two piles gets no count at all.
TEST(References, CountsReachUpToThePileAndNoFurther) {
  testing::FixtureDataset fx;
  testing::add_table(fx, "table");
  fx.add_object_config("toy_book", fx.add_box_mesh("book", {0.1, 0.1, 0.1}));
  fx.add_scene("s", {{"object_instances",
                      {testing::FixtureDataset::instance("toy_table", {0, 0, 0}),
                       testing::FixtureDataset::instance("toy_book", testing::hab(-0.3, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(0.0, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(0.0, 0, 0.85)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(0.3, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_table", testing::hab(3, 0, 0)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(2.7, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(2.7, 0, 0.85)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(3.0, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(3.3, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(3.3, 0, 0.85))}}});
  const auto b = testing::build_fixture_scene(fx, "s");
  const auto& g = b.graph;
  const episode::WorldState s = episode::initial_state(g);
  const graph::PlatformId first = episode::furniture_platform_of(g, s, g.find_object("book_1"));
  for (const char* name : {"book_1", "book_4"}) {
    const auto r = refer_to(g, s, name);
    ASSERT_TRUE(r.has_value()) << name;
    EXPECT_THAT(r->phrase(), ::testing::AnyOf("the leftmost book", "the rightmost book")) << name;
    EXPECT_EQ(resolve(g, s, first, *r, Ambiguity::kCategory), (std::vector<graph::ObjectId>{g.find_object(name)}))
        << name << ": " << r->phrase();
  }
  EXPECT_NE(refer_to(g, s, "book_1")->phrase(), refer_to(g, s, "book_4")->phrase());
  // Past the pile the count is no longer clear: the second book from the left is no book.
  const graph::PlatformId second = episode::furniture_platform_of(g, s, g.find_object("book_8"));
  for (const Relation side : {Relation::kFromLeft, Relation::kFromRight}) {
    for (int rank = 1; rank <= 3; ++rank) {
      Reference r;
      r.relation = side;
      r.noun = "book";
      r.rank = rank;
      const auto picked = resolve(g, s, second, r, Ambiguity::kCategory);
      EXPECT_NE(picked, (std::vector<graph::ObjectId>{g.find_object("book_8")})) << r.phrase();
    }
  }
  const auto between = refer_to(g, s, "book_8");
  if (between) {
    EXPECT_THAT(between->phrase(), ::testing::Not(::testing::HasSubstr("most"))) << between->phrase();
    EXPECT_THAT(between->phrase(), ::testing::Not(::testing::HasSubstr(" from the "))) << between->phrase();
  }
}

// A pile is no chain (two books side by side on a wider one): only its bottom is counted in it,
// and it no longer keeps the stacks beside it from being counted (apt_1's top wall-cabinet shelf:
// its three other books were left out of Levels 1-2). Stacks are counted from either end, never
// past a lone book (a person may count it as a stack or not). Checked in the arrival view too.
TEST(References, APileNamesItsBottomAndLeavesTheStacksBesideItCountable) {
  testing::FixtureDataset fx;
  testing::add_table(fx, "table");
  fx.add_object_config("toy_book", fx.add_box_mesh("book", {0.1, 0.06, 0.1}));
  nlohmann::json wide = testing::FixtureDataset::instance("toy_book", testing::hab(0.25, 0, 0.75));
  wide["non_uniform_scale"] = {3.0, 1.0, 1.0};
  fx.add_scene("s", {{"object_instances",
                      {testing::FixtureDataset::instance("toy_table", {0, 0, 0}),
                       // a stack of two on the left
                       testing::FixtureDataset::instance("toy_book", testing::hab(-0.3, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(-0.3, 0, 0.81)),
                       // a pile on the right: two books side by side on a wide one
                       wide, testing::FixtureDataset::instance("toy_book", testing::hab(0.17, 0, 0.81)),
                       testing::FixtureDataset::instance("toy_book", testing::hab(0.33, 0, 0.81)),
                       // a lone book between them
                       testing::FixtureDataset::instance("toy_book", testing::hab(-0.06, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_table", testing::hab(3, 0, 0))}}});
  auto b = testing::build_fixture_scene(fx, "s");
  // Seen from the rear, as a table against a wall would be: the stacks stand side by side.
  const graph::PlatformId table = b.graph.objects[b.graph.find_object("book_1")].parent;
  b.graph.platforms[table].default_side = 0;
  const auto& g = b.graph;
  const episode::WorldState s = episode::initial_state(g);
  ASSERT_EQ(table, episode::furniture_platform_of(g, s, g.find_object("book_1")));
  ASSERT_EQ(g.objects[g.find_object("book_4")].parent, g.objects[g.find_object("book_3")].platforms.front());
  ASSERT_EQ(g.objects[g.find_object("book_5")].parent, g.objects[g.find_object("book_3")].platforms.front());
  const std::map<std::string, std::string> expected = {
      {"book_1", "the book at the bottom of the leftmost stack"},
      {"book_2", "the book at the top of the leftmost stack"},
      {"book_3", "the book at the bottom of the rightmost stack"}};
  const render::SceneGeometry geometry(b.scene, g);
  const render::VisibilityOracle seeing(g, geometry);
  for (const auto& [name, phrase] : expected) {
    const graph::ObjectId o = g.find_object(name);
    for (const render::VisibilityOracle* oracle : {static_cast<const render::VisibilityOracle*>(nullptr), &seeing}) {
      // The stack's bottom shows only its edge under the book of its size: not clearly seen.
      if (oracle != nullptr && name == "book_1") continue;
      const auto r = refer(g, {&s}, o, table, Ambiguity::kCategory, oracle).reference;
      ASSERT_TRUE(r.has_value()) << name << (oracle ? " in the picture" : "");
      EXPECT_EQ(r->phrase(), phrase) << name;
      EXPECT_EQ(resolve(g, s, table, *r, Ambiguity::kCategory), (std::vector<graph::ObjectId>{o})) << phrase;
    }
  }
  // Above the pile's bottom, nothing counted in it names one book.
  for (const Relation relation : {Relation::kFromTop, Relation::kFromBottom}) {
    for (int rank = 1; rank <= 2; ++rank) {
      if (relation == Relation::kFromBottom && rank == 1) continue;
      const Reference r{relation, "book", "", rank, Row::kNone, 1, true};
      EXPECT_GT(resolve(g, s, table, r, Ambiguity::kCategory).size(), 1u) << r.phrase();
    }
  }
  // Counting past the lone book, the pile is the second or the third stack: neither is said.
  for (const int stack : {2, 3}) {
    const Reference r{Relation::kFromBottom, "book", "", 1, Row::kNone, stack, false};
    EXPECT_NE(resolve(g, s, table, r, Ambiguity::kCategory), (std::vector<graph::ObjectId>{g.find_object("book_3")}))
        << r.phrase();
  }
  // As JSON and back; a count from the right needs a stack.
  const Reference rightmost{Relation::kFromTop, "book", "", 1, Row::kNone, 1, true};
  EXPECT_EQ(Reference::from_json(rightmost.to_json()).phrase(), "the book at the top of the rightmost stack");
  EXPECT_THROW(Reference::from_json({{"relation", "from_top"}, {"noun", "book"}, {"rank", 1}, {"stack_from", "right"}}),
               mtg::Error);
  EXPECT_THROW(Reference::from_json({{"relation", "from_top"}, {"noun", "book"}, {"rank", 1}, {"stack", 1},
                                     {"stack_from", "up"}}),
               mtg::Error);
  for (const char* name : {"book_4", "book_5"}) {
    const auto r = refer_to(g, s, name);
    if (r) {
      EXPECT_THAT(r->phrase(), ::testing::Not(HasSubstr("stack"))) << name;
    }
  }
}

// Level 4 texts name the instances their goals need: "toy box from table_0" alone would match
// three boxes, so the text carries a reference (and a close-up), or the task is not made.
TEST(References, LevelFourTextsNameTheObjectsTheirGoalsNeed) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  TaskOptions o;
  o.levels = {4};
  const GenerationResult r = generate_tasks(b.scene, b.graph, o);
  int named = 0;
  for (const Task& t : r.set.tasks) {
    EXPECT_THAT(audit_task(b.graph, t, o), ::testing::IsEmpty()) << t.text;
    for (const Identification& id : t.identify) {
      EXPECT_THAT(t.text, HasSubstr(id.phrase.substr(4) + " from ")) << t.text;
      ++named;
    }
  }
  EXPECT_GT(named, 0);
}

// What rests on an item travels with it: a box carrying a box does not fit under a shelf that
// takes either box alone, and startplace says why.
TEST(Stacks, TheClearanceTestCountsWhatRestsOnTheItem) {
  testing::FixtureDataset fx;
  testing::add_table(fx, "table");
  // A shelf: a board at 0.30 m under a board at 0.48 m (0.14 m of free height on the lower one).
  fx.add_object_config("toy_shelf", fx.add_boxes_mesh("shelf", {{{0.8, 0.02, 0.4}, {0, 0.29, 0}},
                                                                {{0.8, 0.02, 0.4}, {0, 0.47, 0}},
                                                                {{0.02, 0.48, 0.4}, {-0.39, 0, 0}},
                                                                {{0.02, 0.48, 0.4}, {0.39, 0, 0}}}));
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.1, 0.1, 0.1}));
  fx.add_scene("s", {{"object_instances",
                      {testing::FixtureDataset::instance("toy_table", {0, 0, 0}),
                       testing::FixtureDataset::instance("toy_box", testing::hab(-0.2, 0, 0.75)),
                       testing::FixtureDataset::instance("toy_box", testing::hab(-0.2, 0, 0.85)),
                       testing::FixtureDataset::instance("toy_shelf", testing::hab(2.5, 0, 0))}}});
  const auto b = testing::build_fixture_scene(fx, "s");
  const auto& g = b.graph;
  graph::PlatformId shelf;
  for (const graph::PlatformId p : g.navigable) {
    if (g.platforms[p].clearance < 0.2) shelf = p;
  }
  ASSERT_TRUE(shelf.valid()) << "the lower board is a platform with little free height";
  const auto bottom = g.find_object("box_1");
  episode::WorldState s = episode::initial_state(g);
  EXPECT_NEAR(episode::stack_height(g, s, bottom), 0.2, 0.01);
  episode::pick(g, s, bottom);
  s.at_platform = shelf;
  s.side = g.platforms[shelf].default_side;
  s.phase = episode::Phase::kAtPlatform;
  const episode::StepOutcome out = episode::apply_action(g, s, "startplace", {}, {});
  EXPECT_FALSE(out.applied);
  EXPECT_THAT(out.hint, HasSubstr("with what stands on it"));
  // The generator never sends the stack there, and counts what it left out.
  TaskOptions o;
  o.levels = {1, 2};
  const GenerationResult r = generate_tasks(b.scene, g, o);
  for (const Task& t : r.set.tasks) {
    EXPECT_FALSE(t.item == "box_1" && t.destination == g.platforms[shelf].name) << t.text;
  }
  EXPECT_GT(r.set.dropped.by_reason.at("stack").at(2), 0);
}

// The memo Level 3 shares answers as refer() does, in its base state and in the state after each
// atomic task: where a box left a table, or moved along it (box_3 put back on table_0 keeps the
// boxes' order, only its footprint tells), the table names its boxes differently, and the memo
// must not answer for it from the base state. Asked twice, the second time from what it kept.
TEST(References, TheMemoAnswersAsReferDoesInStatesDerivedFromItsBase) {
  testing::FixtureDataset fx;
  const auto b = testing::two_tables(fx);
  const auto& g = b.graph;
  const episode::WorldState initial = episode::initial_state(g);
  const ReferenceMemo memo(g, initial, Ambiguity::kCategory);
  const std::vector<AtomicTask> atomic = enumerate_atomic(g, initial, TaskOptions{});
  ASSERT_GE(atomic.size(), 2u);
  std::vector<episode::WorldState> states = {initial};
  for (const AtomicTask& task : atomic) {
    states.push_back(initial);
    apply_effect(g, states.back(), task);
  }
  const auto words = [](const Referral& r) { return r ? r->to_json().dump() : std::string(r.occluded ? "occluded" : "none"); };
  int asked = 0, differ_from_base = 0;
  for (int pass = 0; pass < 2; ++pass) {
    for (const episode::WorldState& s : states) {
      for (const graph::PlatformId p : g.navigable) {
        std::vector<graph::ObjectId> held = {graph::ObjectId()};
        for (const graph::ObjectId o : episode::pickable_on(g, s, p)) held.push_back(o);
        for (const graph::ObjectId o : episode::everything_on(g, s, p)) {
          for (const graph::ObjectId h : held) {
            const std::string expected = words(refer_in(g, s, o, p, h, Ambiguity::kCategory));
            EXPECT_EQ(words(memo.refer(s, o, p, h)), expected) << g.objects[o].name << " held " << h;
            differ_from_base += expected != words(refer_in(g, initial, o, p, h, Ambiguity::kCategory)) ? 1 : 0;
            ++asked;
          }
        }
      }
    }
  }
  EXPECT_GT(asked, 100);
  EXPECT_GT(differ_from_base, 0) << "no moved state named an object differently: the test proves nothing";
}

}  // namespace
}  // namespace mtg::tasks
