// Level 4 on the shipped apartments and on held-out arrangements, checked without the generator's
// own helpers (issue 54): the words of every text, read back through its template, mean exactly
// the objects its goal lists (a word's own noun and the nouns it covers, from the graph's noun
// table, scoped to the platforms the text names); every object the oracle picks stands on a
// platform the text names (a person knows where to look without searching the home); the step
// limit leaves room beyond the oracle's plan; and the kinds are many and none dominates.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>
#include <regex>
#include <set>

#include "core/episode/goals.h"
#include "core/episode/rules.h"
#include "core/tasks/generator.h"
#include "core/tasks/outcome.h"
#include "tests/support/shipped_data.h"
#include "tests/support/shipped_scene.h"

namespace mtg::tasks {
namespace {

using graph::ObjectId;
using graph::PlatformId;

using Checked = testing::ShippedScene;

// A shipped apartment, or (remix_seed) its items rearranged as `mtg scene remix` does.
Checked load(const std::string& name, std::optional<std::uint64_t> remix_seed) {
  return remix_seed ? testing::load_remixed_scene(name, *remix_seed) : testing::load_shipped_scene(name);
}

// The placeholder values of `text`, read through its template, or nullopt when it does not match.
std::optional<std::map<std::string, std::string>> values_of(const std::string& tmpl, const std::string& text) {
  std::string pattern;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < tmpl.size();) {
    if (tmpl[i] == '{') {
      const std::size_t end = tmpl.find('}', i);
      const std::string name = tmpl.substr(i + 1, end - i - 1);
      const auto seen = std::find(names.begin(), names.end(), name);
      if (seen == names.end()) {
        names.push_back(name);
        // A platform or furniture name is one word ("shelf_02_3_platform_1"); an object's words may
        // hold "on" ("the cup on the plate from ..."), so only the names fix where they end.
        static const std::set<std::string> kOneWord = {"source", "source2", "source3", "target",
                                                       "target2", "layer", "layer2", "furniture"};
        pattern += kOneWord.count(name) != 0 ? "([A-Za-z0-9_]+)" : "(.+?)";
      } else {
        pattern += "\\" + std::to_string(seen - names.begin() + 1);
      }
      i = end + 1;
    } else {
      const char c = tmpl[i++];
      if (std::string("\\^$.|?*+()[]{}").find(c) != std::string::npos) pattern += '\\';
      pattern += c;
    }
  }
  std::smatch m;
  if (!std::regex_match(text, m, std::regex(pattern))) return std::nullopt;
  std::map<std::string, std::string> out;
  for (std::size_t k = 0; k < names.size(); ++k) out[names[k]] = m[k + 1].str();
  return out;
}

// What a person reads as a category word, and the nouns it means: each object's noun (or its
// class where it has none) in the singular and the plural, and each covering word of the noun
// table, in the scene's own data.
class Nouns {
 public:
  explicit Nouns(const graph::SceneGraph& g) : g_(g) {
    auto add = [&](const std::string& key, const std::string& plural_words) {
      std::string text = key;
      std::replace(text.begin(), text.end(), '_', ' ');
      for (const std::string& form : {text, plural_words.empty() ? regular_plural(text) : plural_words}) {
        words_[form] = key;
      }
    };
    for (const ObjectId o : g.objects.ids()) {
      const graph::GraphObject& obj = g.objects[o];
      add(key_of(o), obj.noun_plural);
    }
    for (const auto& [word, nouns] : g.noun_covers) add(word, "");
  }
  std::string key_of(ObjectId o) const {
    const graph::GraphObject& obj = g_.objects[o];
    return !obj.noun.empty() ? obj.noun : (obj.category.empty() ? obj.short_name : obj.category);
  }
  // The noun key a category word stands for, or "" when the word is none of the scene's.
  std::string key_of_word(const std::string& word) const {
    const auto it = words_.find(word);
    return it == words_.end() ? "" : it->second;
  }
  bool means(const std::string& key, ObjectId o) const {
    const std::string own = key_of(o);
    if (own == key) return true;
    const auto it = g_.noun_covers.find(key);
    return it != g_.noun_covers.end() && it->second.count(own) != 0;
  }

 private:
  static std::string regular_plural(const std::string& w) {
    if (w.empty()) return w;
    const char last = w.back();
    if (last == 'y' && w.size() > 1 && std::string("aeiou").find(w[w.size() - 2]) == std::string::npos) {
      return w.substr(0, w.size() - 1) + "ies";
    }
    if (last == 's' || last == 'x' || last == 'z' || w.ends_with("ch") || w.ends_with("sh")) return w + "es";
    return w + "s";
  }
  const graph::SceneGraph& g_;
  std::map<std::string, std::string> words_;
};

class Level4Checker {
 public:
  Level4Checker(const graph::SceneGraph& g) : g_(g), nouns_(g), initial_(episode::initial_state(g)) {
    for (const ObjectId o : g.objects.ids()) {
      if (!g.objects[o].pickable()) continue;
      const PlatformId p = episode::furniture_platform_of(g, initial_, o);
      if (p.valid()) on_[p].push_back(o);
      home_.push_back(o);
    }
  }

  std::vector<std::string> check(const Task& t, const OutcomeTemplate& tmpl) const {
    std::vector<std::string> problems;
    const auto values = values_of(tmpl.text, t.text);
    if (!values) return {"the text does not read as its template " + tmpl.id};
    const episode::OutcomeGoal goal = episode::task_goal_from_json(g_, t.goal).outcome;
    auto platform = [&](const std::string& key) { return g_.find_platform(values->at(key)); };
    // Every object on the named platforms that the category word means.
    auto meant = [&](const std::string& word_key, std::vector<std::string> scopes) {
      // "category" / "categories", "category2" / "categories2": whichever the text uses.
      std::string key;
      for (const std::string& k : {word_key, "categories" + word_key.substr(std::string("category").size())}) {
        if (key.empty() && values->count(k) != 0) key = nouns_.key_of_word(values->at(k));
      }
      std::vector<ObjectId> out;
      if (key.empty()) {
        problems.push_back("no category word for " + word_key);
        return out;
      }
      std::vector<ObjectId> pool;
      if (scopes.empty()) pool = home_;
      for (const std::string& scope : scopes) {
        const auto it = on_.find(platform(scope));
        if (it != on_.end()) pool.insert(pool.end(), it->second.begin(), it->second.end());
      }
      for (const ObjectId o : pool) {
        if (nouns_.means(key, o)) out.push_back(o);
      }
      return out;
    };
    auto everything_on = [&](const std::string& scope) {
      const auto it = on_.find(platform(scope));
      return it == on_.end() ? std::vector<ObjectId>{} : it->second;
    };
    auto expect_same = [&](const std::string& what, std::vector<ObjectId> a, std::vector<ObjectId> b) {
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      if (a != b) {
        problems.push_back(what + ": the words mean " + std::to_string(b.size()) + " objects, the goal lists " +
                           std::to_string(a.size()));
      }
    };
    const auto& all = goal.all;
    auto list = [&](std::size_t k, int which) {
      if (k >= all.size()) return std::vector<ObjectId>{};
      return which == 1 ? all[k].objects : all[k].objects2;
    };
    // Category words that mean one goal list each: (predicate, list, word, the platforms it is
    // scoped to; none: the home).
    struct WordRule {
      std::size_t predicate;
      int list;
      const char* word;
      std::vector<std::string> scopes;
    };
    using K = OutcomeKind;
    static const std::map<OutcomeKind, std::vector<WordRule>> kRules = {
        {K::kGatherCategory, {{0, 1, "category", {"source"}}}},
        {K::kClearCategory, {{0, 1, "category", {"source"}}}},
        {K::kConsolidate, {{0, 1, "category", {}}}},
        {K::kSetUp, {{0, 1, "category", {"source"}}, {0, 2, "category2", {"source2"}}}},
        {K::kSort, {{0, 1, "category", {"source"}}, {1, 1, "category2", {"source"}}}},
        {K::kLeaveExactly, {{0, 1, "category", {"source"}}}},
        {K::kThinOut, {{0, 1, "category", {"source"}}}},
        {K::kBringSome, {{0, 1, "category", {"source"}}}},
        {K::kSpreadOut, {{0, 1, "category", {"source"}}}},
        {K::kGroupAround, {{0, 1, "category", {"source"}}}},
        {K::kPutInside, {{0, 1, "category", {"source"}}}},
        {K::kKeepOne, {{0, 1, "category", {"source"}}, {1, 1, "category", {"source"}}}},
        {K::kSplit, {{0, 1, "category", {"source"}}, {1, 1, "category", {"source"}}, {2, 1, "category", {"source"}}}},
        {K::kLayOut,
         {{0, 1, "category", {"source"}}, {1, 1, "category2", {"source2"}}, {2, 1, "category3", {"source3"}}}},
        {K::kBesideKind, {{0, 2, "category", {"target"}}}},
        {K::kGatherTwo, {{0, 1, "category", {"source", "source2"}}}},
    };
    if (const auto rules = kRules.find(tmpl.kind); rules != kRules.end()) {
      for (const WordRule& w : rules->second) expect_same(w.word, list(w.predicate, w.list), meant(w.word, w.scopes));
    }
    switch (tmpl.kind) {
      case OutcomeKind::kKeepOnly: {
        const auto kept = meant("category", {"source"});
        std::vector<ObjectId> others;
        for (const ObjectId o : everything_on("source")) {
          if (std::find(kept.begin(), kept.end(), o) == kept.end()) others.push_back(o);
        }
        expect_same("everything else", list(0, 1), others);
        expect_same("categories", list(1, 1), kept);
        break;
      }
      case OutcomeKind::kAllButOne: {
        std::vector<ObjectId> both = list(0, 1);
        for (const ObjectId o : list(1, 1)) both.push_back(o);
        expect_same("category", both, meant("category", {"source"}));
        break;
      }
      case OutcomeKind::kJoinKind:
        if (meant("category", {"target"}).size() < 2) problems.push_back("the other ones are not on the target");
        break;
      case OutcomeKind::kClearPlatform:
      case OutcomeKind::kMoveAll:
        expect_same("everything", list(0, 1), everything_on("source"));
        break;
      case OutcomeKind::kMoveLayer:
        expect_same("everything", list(0, 1), everything_on("layer"));
        break;
      default:
        break;  // objects named one by one: their references are checked by audit_task
    }
    findable(t, problems);
    if (t.step_limit < static_cast<int>(t.oracle.size()) + 3) problems.push_back("the step limit leaves no margin");
    return problems;
  }

 private:
  // Every pick of the oracle's plan happens at a platform the text names (or its furniture).
  void findable(const Task& t, std::vector<std::string>& problems) const {
    auto named = [&](const std::string& name) {
      for (std::size_t at = t.text.find(name); at != std::string::npos; at = t.text.find(name, at + 1)) {
        const std::size_t end = at + name.size();
        const bool word_end = end == t.text.size() || !(std::isalnum(static_cast<unsigned char>(t.text[end])) || t.text[end] == '_');
        const bool word_start = at == 0 || !(std::isalnum(static_cast<unsigned char>(t.text[at - 1])) || t.text[at - 1] == '_');
        if (word_start && word_end) return true;
      }
      return false;
    };
    episode::WorldState s = initial_;
    episode::RuleOptions rules;
    rules.step_limit = t.step_limit;
    for (const std::string& key : t.oracle) {
      if (key.size() > 1 && key[0] == 'o' && std::isdigit(static_cast<unsigned char>(key[1]))) {
        const PlatformId at = s.at_platform;
        const bool ok = at.valid() && (named(g_.platforms[at].name) ||
                                       (g_.platforms[at].owner.valid() && named(g_.objects[g_.platforms[at].owner].name)));
        if (!ok) problems.push_back("the oracle picks at " + (at.valid() ? g_.platforms[at].name : "?") + ", which the text never names");
      }
      episode::apply_action(g_, s, key, {}, rules);
    }
    // A person who moves each listed object on its own (five keys a move) and ends still fits.
    const episode::OutcomeGoal goal = episode::task_goal_from_json(g_, t.goal).outcome;
    std::set<ObjectId> listed;
    for (const episode::SetPredicate& p : goal.all) listed.insert(p.objects.begin(), p.objects.end());
    int moved = 0;
    for (const ObjectId o : listed) {
      moved += episode::furniture_platform_of(g_, initial_, o) != episode::furniture_platform_of(g_, s, o) ? 1 : 0;
    }
    if (t.step_limit < 5 * moved + 1) {
      problems.push_back("moving its " + std::to_string(moved) + " objects one by one does not fit the step limit");
    }
  }

  const graph::SceneGraph& g_;
  Nouns nouns_;
  episode::WorldState initial_;
  std::map<PlatformId, std::vector<ObjectId>> on_;
  std::vector<ObjectId> home_;
};

struct Arrangement {
  const char* apartment;
  int remix_seed;  // < 0: as shipped
};

class Level4Words : public ::testing::TestWithParam<Arrangement> {};

TEST_P(Level4Words, EveryCategoryWordMeansTheGoalsObjectsAndEveryPickIsWhereTheTextSays) {
  MTG_REQUIRE_SHIPPED_DATA();
  const Arrangement a = GetParam();
  const Checked c = load(a.apartment, a.remix_seed < 0 ? std::nullopt : std::optional<std::uint64_t>(a.remix_seed));
  TaskOptions options;
  options.levels = {4};
  const GenerationResult r = generate_tasks(c.scene, c.graph, options);
  const auto templates = load_templates("builtin");
  std::map<std::string, const OutcomeTemplate*> by_id;
  for (const OutcomeTemplate& t : templates) by_id[t.id] = &t;
  const Level4Checker checker(c.graph);
  std::map<std::string, int> per_kind;
  std::set<std::string> used_templates;
  int reported = 0, checked = 0;
  for (const Task& t : r.set.tasks) {
    const auto it = by_id.find(t.template_id);
    ASSERT_NE(it, by_id.end()) << t.id;
    per_kind[to_string(it->second->kind)] += 1;
    used_templates.insert(t.template_id);
    ++checked;
    for (const std::string& p : checker.check(t, *it->second)) {
      if (++reported <= 20) ADD_FAILURE() << t.id << ": " << p << "  [" << t.text << "]";
    }
  }
  int largest = 0;
  for (const auto& [kind, n] : per_kind) largest = std::max(largest, n);
  std::printf("[ level 4 ] %s: %d tasks checked, %zu kinds, %zu templates used, largest kind %.1f %%\n",
              c.scene.name.c_str(), checked, per_kind.size(), used_templates.size(), 100.0 * largest / std::max(1, checked));
  EXPECT_EQ(reported, 0);
  EXPECT_GE(checked, 6200) << "the paper's average per apartment";
  EXPECT_LE(largest, checked / 5 + 1) << "no kind above a fifth";
  // A kind that makes nothing says which precondition stopped it, or that its candidates were dropped.
  for (const OutcomeTemplate& t : templates) {
    const std::string kind = to_string(t.kind);
    if (per_kind.count(kind) != 0) continue;
    const bool said = std::any_of(r.set.warnings.begin(), r.set.warnings.end(), [&](const std::string& w) {
      return w.find("no " + kind + " task") != std::string::npos;
    });
    EXPECT_TRUE(said) << kind << " is absent without a word";
    per_kind[kind] += 0;
  }
  for (const std::string& w : r.set.warnings) std::printf("[ level 4 ] %s\n", w.c_str());
  if (a.remix_seed < 0) {
    EXPECT_GE(std::count_if(per_kind.begin(), per_kind.end(), [](const auto& k) { return k.second > 0; }), 29);
  }
}

std::string arrangement_name(const ::testing::TestParamInfo<Arrangement>& p) {
  return std::string(p.param.apartment) + (p.param.remix_seed < 0 ? "" : "_remix_" + std::to_string(p.param.remix_seed));
}

INSTANTIATE_TEST_SUITE_P(Apartments, Level4Words,
                         ::testing::Values(Arrangement{"apt_0", -1}, Arrangement{"apt_1", -1}, Arrangement{"apt_2", -1},
                                           Arrangement{"apt_0", 7}, Arrangement{"apt_2", 11}),
                         arrangement_name);

}  // namespace
}  // namespace mtg::tasks
