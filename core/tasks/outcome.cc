#include "core/tasks/outcome.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>

#include "core/episode/placement.h"
#include "core/episode/rules.h"
#include "core/tasks/identify.h"
#include "core/tasks/outcome_templates_embedded.h"
#include "core/tasks/phrasing.h"
#include "core/tasks/referring.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/json_file.h"
#include "core/util/rng.h"

namespace mtg::tasks {
namespace {

using episode::SetPredicate;
using episode::WorldState;

// Each kind's name and the placeholders its templates may and must use: the one table of kinds.
struct KindSpec {
  OutcomeKind kind;
  const char* name;
  std::set<std::string> allowed;
  std::vector<std::set<std::string>> required;  // each: at least one of these
};

const std::vector<KindSpec>& kinds() {
  using K = OutcomeKind;
  static const std::vector<KindSpec> k = {
      {K::kGatherCategory, "gather_category", {"source", "target", "category", "categories", "count"},
       {{"source"}, {"target"}, {"category", "categories"}}},
      {K::kConsolidate, "consolidate", {"target", "category", "categories", "count"}, {{"target"}, {"category", "categories"}}},
      {K::kClearPlatform, "clear_platform", {"source", "count"}, {{"source"}}},
      {K::kClearCategory, "clear_category", {"source", "category", "categories", "count"},
       {{"source"}, {"category", "categories"}}},
      {K::kArrangeOn, "arrange_on", {"object", "object2", "target"}, {{"object"}, {"object2"}, {"target"}}},
      {K::kTogether, "together", {"object", "object2"}, {{"object"}, {"object2"}}},
      {K::kSetUp, "set_up", {"target", "category", "category2"}, {{"target"}, {"category"}, {"category2"}}},
      {K::kPutAway, "put_away", {"object", "furniture"}, {{"object"}, {"furniture"}}},
      {K::kSort, "sort", {"source", "target", "target2", "category", "categories", "category2", "categories2"},
       {{"source"}, {"target"}, {"target2"}, {"category", "categories"}, {"category2", "categories2"}}},
      {K::kMoveLayer, "move_layer", {"layer", "layer2", "furniture", "count"}, {{"layer"}, {"layer2"}, {"furniture"}}},
      {K::kPair, "pair", {"object", "object2"}, {{"object"}, {"object2"}}},
  };
  return k;
}

const KindSpec* spec_named(const std::string& name) {
  for (const KindSpec& k : kinds()) {
    if (name == k.name) return &k;
  }
  return nullptr;
}

std::set<std::string> placeholders_of(const std::string& text) {
  std::set<std::string> out;
  for (std::size_t pos = 0; (pos = text.find('{', pos)) != std::string::npos;) {
    const std::size_t end = text.find('}', pos);
    if (end == std::string::npos) break;
    out.insert(text.substr(pos + 1, end - pos - 1));
    pos = end + 1;
  }
  return out;
}

using graph::ObjectId;
using graph::PlatformId;

// The key Level 4 groups items by: the noun under the noun rule (what a person calls it, so
// "every kitchen utensil" never counts a sponge dish), else the semantic category, or the model
// name without one.
std::string category_key(const graph::GraphObject& obj, Ambiguity rule) {
  if (rule == Ambiguity::kNoun && !obj.noun.empty()) return obj.noun;
  return obj.category.empty() ? obj.short_name : obj.category;
}

// What the generator needs about the scene, computed once.
struct SceneFacts {
  std::vector<PlatformId> navigable;
  std::map<PlatformId, std::vector<ObjectId>> items_on;       // navigable platform -> pickable items
  std::map<std::string, std::vector<ObjectId>> by_category;  // category -> pickable items (navigable)
  std::map<ObjectId, std::string> category_of;                // item -> category key
  std::map<std::string, std::string> plural_of;               // category key -> its plural words
  std::vector<ObjectId> multilayer;                           // furniture with >= 2 navigable platforms
};

SceneFacts facts(const graph::SceneGraph& g, const WorldState& s, Ambiguity rule) {
  SceneFacts f;
  f.navigable = g.navigable;
  for (const PlatformId p : g.navigable) {
    f.items_on[p] = episode::pickable_on(g, s, p);
    for (const ObjectId o : f.items_on[p]) {
      const std::string cat = category_key(g.objects[o], rule);
      f.category_of[o] = cat;
      f.by_category[cat].push_back(o);
      // A word that covers its noun counts it too ("every cup" takes in the mugs).
      if (rule == Ambiguity::kNoun) {
        for (const std::string& word : g.words_covering(cat)) f.by_category[word].push_back(o);
      }
      const std::string& irregular = g.objects[o].noun_plural;
      if (rule == Ambiguity::kNoun && !irregular.empty()) f.plural_of[cat] = irregular;
    }
  }
  for (const ObjectId i : g.objects.ids()) {
    int layers = 0;
    for (const PlatformId p : g.objects[i].platforms) layers += g.platforms[p].navigable ? 1 : 0;
    if (layers >= 2) f.multilayer.push_back(i);
  }
  return f;
}

// Object-level placeholders are drawn this many times per platform-level binding.
constexpr std::size_t kSamples = 6;

struct Move {
  ObjectId object;
  std::vector<PlatformId> platforms;  // acceptable destinations, tried in order
  ObjectId next_to;                   // place in one of this object's free spaces
};

struct Plan {
  std::vector<std::string> keys;
  WorldState after;  // the world once the keys are played
};

// Plays a greedy plan with the episode rules. Returns the keys and the world they leave, or
// nullopt when a move fails.
std::optional<Plan> plan_moves(const graph::SceneGraph& g, WorldState s, const std::vector<Move>& moves,
                               const TaskOptions& options, episode::PlacementMemo* memo) {
  episode::RuleOptions rules = options.rules;
  rules.step_limit = 1 << 20;
  std::vector<std::string> keys;
  auto play = [&](const std::string& key) {
    return episode::apply_action(g, s, key, {}, rules, memo).applied ? (keys.push_back(key), true) : false;
  };
  for (const Move& m : moves) {
    const PlatformId from = episode::furniture_platform_of(g, s, m.object);
    if (!from.valid() || g.platforms[from].label == 0) return std::nullopt;
    const auto items = episode::pickable_on(g, s, from);
    const auto k = std::find(items.begin(), items.end(), m.object) - items.begin();
    if (k == static_cast<long>(items.size())) return std::nullopt;
    if (!play(graph::navigation_key(g.platforms[from].label)) ||
        !play("o" + std::to_string(k + 1))) {
      return std::nullopt;
    }
    bool placed = false;
    for (const PlatformId to : m.platforms) {
      const graph::Platform& dest = g.platforms[to];
      if (dest.label == 0) continue;
      if (episode::stack_height(g, s, m.object) > dest.clearance) continue;
      WorldState trial = s;
      const std::size_t mark = keys.size();
      if (!play(graph::navigation_key(dest.label)) || !play("startplace")) {
        s = trial;
        keys.resize(mark);
        continue;
      }
      const auto targets =
          episode::place_targets(g, s, to, static_cast<graph::Side>(s.side), rules.min_region_size, memo);
      const episode::FeasibleCentres feasible = episode::held_feasible_centres(g, s, to, memo);
      for (const episode::PlaceTarget& t : targets) {
        const bool wanted = m.next_to.valid() ? t.anchor == m.next_to : t.key == episode::kAnywhereKey;
        if (!wanted || !episode::resolve_target(g, s, to, t, feasible, memo)) continue;
        placed = play(t.key);
        if (placed) break;
      }
      if (placed) break;
      s = trial;
      keys.resize(mark);
    }
    if (!placed) return std::nullopt;
  }
  return Plan{std::move(keys), std::move(s)};
}

std::string category_text(const std::string& c) {
  std::string out = c;
  std::replace(out.begin(), out.end(), '_', ' ');
  return out;
}

// An object named in a text ("{object}"): its noun, a reference when it has look-alikes on its
// platform, and the platform ("leftmost book from shelf_2"), with what those words pick out.
struct NamedObject {
  std::string words;
  std::vector<ObjectId> selects;
  std::vector<Identification> lookalikes;
};

class Instantiator {
 public:
  Instantiator(const graph::SceneGraph& g, const WorldState& s, const TaskOptions& options,
               const render::VisibilityOracle* seeing, DropCounts& dropped,
               episode::PlacementMemo* memo)
      : g_(g), s_(s), options_(options), seeing_(seeing), dropped_(dropped), memo_(memo),
        f_(facts(g, s, options.ambiguity)) {}

  void run(const OutcomeTemplate& t, std::vector<OutcomeTask>& out) {
    tmpl_ = &t;
    out_ = &out;
    switch (t.kind) {
      case OutcomeKind::kGatherCategory: return gather_category();
      case OutcomeKind::kConsolidate: return consolidate();
      case OutcomeKind::kClearPlatform: return clear_platform();
      case OutcomeKind::kClearCategory: return clear_category();
      case OutcomeKind::kArrangeOn: return arrange_on();
      case OutcomeKind::kTogether: return together();
      case OutcomeKind::kSetUp: return set_up();
      case OutcomeKind::kPutAway: return put_away();
      case OutcomeKind::kSort: return sort();
      case OutcomeKind::kMoveLayer: return move_layer();
      case OutcomeKind::kPair: return pair();
    }
  }

 private:
  Rng rng_for(const std::string& binding) const {
    return Rng(derive_seed(options_.seed, fnv1a64("L4/" + tmpl_->id + "/" + binding)));
  }
  std::string pname(PlatformId p) const { return g_.platforms[p].name; }
  // "books", "pairs of shoes": a category's plural as the text writes it.
  std::string plural_text(const std::string& cat) const {
    const auto it = f_.plural_of.find(cat);
    return it != f_.plural_of.end() ? it->second : plural(category_text(cat));
  }
  // Furniture by its instance name, as the platform names the agent reads spell it.
  std::string furniture_name(ObjectId f) const { return g_.objects[f].name; }

  // What category words select, read from the scene rather than from the goal: every item of
  // the category on `platform` (at any depth), or anywhere in the scene for none.
  std::vector<ObjectId> called(const std::string& cat, PlatformId platform = {}) const {
    std::vector<ObjectId> out;
    if (platform.valid()) {
      for (const ObjectId o : episode::pickable_on(g_, s_, platform)) {
        if (category_key(g_.objects[o], options_.ambiguity) == cat) out.push_back(o);
      }
      return out;
    }
    for (const ObjectId i : g_.objects.ids()) {
      if (g_.objects[i].pickable() && category_key(g_.objects[i], options_.ambiguity) == cat) out.push_back(i);
    }
    return out;
  }

  // How the text names one object, or why it cannot (occluded: named in the geometry, but not as
  // its platform's arrival view shows it).
  struct ObjectNaming {
    std::optional<NamedObject> named;
    bool occluded = false;
  };
  ObjectNaming name_object(ObjectId o) const {
    const PlatformId platform = episode::furniture_platform_of(g_, s_, o);
    if (!platform.valid()) return {};
    const auto ref = refer(g_, {&s_}, o, platform, options_.ambiguity, seeing_);
    if (!ref) return {std::nullopt, ref.occluded};
    NamedObject named;
    named.words = ref->phrase().substr(4) + " from " + pname(platform);  // without "the "
    named.selects = resolve(g_, s_, platform, *ref, options_.ambiguity);
    if (ref->relation != Relation::kAlone) {
      named.lookalikes.push_back(make_identification(g_, 0, "object", o, platform, *ref));
    }
    return {std::move(named), false};
  }
  // Names every object, or counts the binding as unidentifiable.
  std::optional<std::vector<NamedObject>> name_objects(std::initializer_list<ObjectId> objects) {
    std::vector<NamedObject> out;
    for (const ObjectId o : objects) {
      ObjectNaming naming = name_object(o);
      if (!naming.named) {
        dropped_.add(naming.occluded ? "occluded" : "unidentifiable", 4);
        return std::nullopt;
      }
      out.push_back(std::move(*naming.named));
    }
    return out;
  }
  int max_moves() const { return options_.level4_max_moves; }

  std::vector<ObjectId> of_category_on(const std::string& cat, PlatformId platform) const {
    std::vector<ObjectId> out;
    for (const ObjectId o : f_.items_on.at(platform)) {
      if (g_.called(cat, f_.category_of.at(o))) out.push_back(o);
    }
    return out;
  }
  std::vector<std::string> categories_on(PlatformId platform) const {
    std::set<std::string> cats;
    for (const ObjectId o : f_.items_on.at(platform)) {
      cats.insert(f_.category_of.at(o));
      for (const std::string& word : g_.words_covering(f_.category_of.at(o))) cats.insert(word);
    }
    return {cats.begin(), cats.end()};
  }
  // Navigable platforms other than `except`, in a seeded order.
  std::vector<PlatformId> shuffled_targets(Rng& rng, const std::set<PlatformId>& except) const {
    std::vector<PlatformId> out;
    for (const PlatformId p : f_.navigable) {
      if (except.count(p) == 0) out.push_back(p);
    }
    rng.shuffle(out);
    return out;
  }
  std::vector<ObjectId> items_not_on(const std::set<PlatformId>& platforms) const {
    std::vector<ObjectId> out;
    for (const auto& [p, items] : f_.items_on) {
      if (platforms.count(p) == 0) out.insert(out.end(), items.begin(), items.end());
    }
    return out;
  }

  // Fills the template, plans, verifies the goal with the judge's predicate, and keeps the task.
  // `selects` holds what the text's words pick out, one set per object list of the goal's
  // predicates (objects, then objects2 where used), computed from the words: the goal must ask
  // for exactly those objects, or the text would not say which ones it wants.
  bool emit(const std::map<std::string, std::string>& values, episode::OutcomeGoal goal,
            const std::vector<Move>& moves, const std::vector<std::vector<ObjectId>>& selects,
            std::vector<Identification> lookalikes = {}) {
    // "All the canisters ... put them" said of one canister misleads: plural words need two.
    const char* plurals[] = {"categories", "categories2"};
    for (std::size_t k = 0; k < 2; ++k) {
      if (values.count(plurals[k]) != 0 && k < selects.size() && selects[k].size() < 2) return false;
    }
    if (!words_match(goal, selects)) {
      dropped_.add("vague", 4);
      return false;
    }
    if (!all_seen(selects)) {  // every object the words count shows where the agent looks for it
      dropped_.add("occluded", 4);
      return false;
    }
    if (episode::outcome_satisfied(g_, s_, goal, options_.goals)) {
      dropped_.add("trivial", 4);
      return false;
    }
    auto plan = plan_moves(g_, s_, moves, options_, memo_);
    if (!plan || !episode::outcome_satisfied(g_, plan->after, goal, options_.goals)) return false;
    OutcomeTask task;
    task.tmpl = tmpl_;
    task.text = tmpl_->text;
    for (const auto& [key, value] : values) replace_all(task.text, "{" + key + "}", value);
    task.goal = std::move(goal);
    task.oracle = std::move(plan->keys);
    task.identify = std::move(lookalikes);
    out_->push_back(std::move(task));
    return true;
  }

  bool all_seen(const std::vector<std::vector<ObjectId>>& selects) const {
    if (seeing_ == nullptr) return true;
    for (const auto& list : selects) {
      for (const ObjectId o : list) {
        const PlatformId platform = episode::furniture_platform_of(g_, s_, o);
        if (!platform.valid()) return false;
        const auto sight = seeing_->arrival_view(s_, platform);
        if (!sight->clearly_visible(o) || !seeing_->mark_readable(s_, platform, o)) return false;
      }
    }
    return true;
  }

  static bool words_match(const episode::OutcomeGoal& goal, const std::vector<std::vector<ObjectId>>& selects) {
    auto same = [](std::vector<ObjectId> a, std::vector<ObjectId> b) {
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      return a == b;
    };
    std::size_t k = 0;
    for (const SetPredicate& p : goal.all) {
      for (const auto* list : {&p.objects, &p.objects2}) {
        if (list == &p.objects2 && p.op != SetPredicate::Op::kAnyPairNear) continue;
        if (k >= selects.size() || !same(*list, selects[k++])) return false;
      }
    }
    return k == selects.size();
  }

  // Tries destinations in a seeded order until one gives a feasible plan.
  template <class Make>
  void try_targets(Rng& rng, const std::set<PlatformId>& except, Make make) {
    int tried = 0;
    for (const PlatformId t : shuffled_targets(rng, except)) {
      if (make(t) || ++tried >= 6) return;
    }
  }

  static SetPredicate all_on(std::vector<ObjectId> objects, std::vector<PlatformId> platforms) {
    return {SetPredicate::Op::kAllOn, std::move(objects), std::move(platforms), {}};
  }

  void gather_category() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        if (objs.size() < 2 || static_cast<int>(objs.size()) > max_moves()) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        try_targets(rng, {src}, [&](PlatformId dst) {
          std::vector<Move> moves;
          for (const ObjectId o : objs) moves.push_back({o, {dst}, {}});
          return emit({{"source", pname(src)}, {"target", pname(dst)}, {"category", category_text(cat)},
                       {"categories", plural_text(cat)}, {"count", std::to_string(objs.size())}},
                      {{all_on(objs, {dst})}}, moves, {called(cat, src)});
        });
      }
    }
  }

  void consolidate() {
    for (const auto& entry : f_.by_category) {
      // Named, not a structured binding: clang before 16 (scripts/fuzz's) cannot capture those.
      const auto& cat = entry.first;
      const auto& objs = entry.second;
      if (objs.size() < 2 || static_cast<int>(objs.size()) > max_moves()) continue;
      Rng rng = rng_for(cat);
      try_targets(rng, {}, [&](PlatformId dst) {
        std::vector<Move> moves;
        for (const ObjectId o : objs) {
          if (episode::furniture_platform_of(g_, s_, o) != dst) moves.push_back({o, {dst}, {}});
        }
        return emit({{"target", pname(dst)}, {"category", category_text(cat)},
                     {"categories", plural_text(cat)}, {"count", std::to_string(objs.size())}},
                    {{all_on(objs, {dst})}}, moves, {called(cat)});
      });
    }
  }

  void clear_platform() {
    for (const PlatformId src : f_.navigable) {
      const auto& objs = f_.items_on.at(src);
      if (objs.empty() || static_cast<int>(objs.size()) > max_moves()) continue;
      // Objects resting on others leave with them: move only the direct children.
      std::vector<ObjectId> direct;
      for (const ObjectId o : objs) {
        if (s_.objects[o].parent == src) direct.push_back(o);
      }
      Rng rng = rng_for(pname(src));
      const auto targets = shuffled_targets(rng, {src});
      std::vector<Move> moves;
      for (const ObjectId o : direct) moves.push_back({o, targets, {}});
      emit({{"source", pname(src)}, {"count", std::to_string(objs.size())}},
           {{{SetPredicate::Op::kNoneOn, objs, {src}, {}}}}, moves, {episode::pickable_on(g_, s_, src)});
    }
  }

  void clear_category() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        if (objs.size() == f_.items_on.at(src).size() || static_cast<int>(objs.size()) > max_moves()) continue;
        bool direct = true;
        for (const ObjectId o : objs) direct = direct && s_.objects[o].parent == src;
        if (!direct) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        const auto targets = shuffled_targets(rng, {src});
        std::vector<Move> moves;
        for (const ObjectId o : objs) moves.push_back({o, targets, {}});
        emit({{"source", pname(src)}, {"category", category_text(cat)}, {"categories", plural_text(cat)},
              {"count", std::to_string(objs.size())}},
             {{{SetPredicate::Op::kNoneOn, objs, {src}, {}}}}, moves, {called(cat, src)});
      }
    }
  }

  void arrange_on() {
    for (const PlatformId dst : f_.navigable) {
      auto pool = items_not_on({dst});
      if (pool.size() < 2) continue;
      Rng rng = rng_for(pname(dst));
      rng.shuffle(pool);
      for (std::size_t k = 0; k + 1 < pool.size() && k < 2 * kSamples; k += 2) {
        const ObjectId a = pool[k], b = pool[k + 1];
        const auto named = name_objects({a, b});
        if (!named) continue;
        emit({{"object", (*named)[0].words}, {"object2", (*named)[1].words}, {"target", pname(dst)}},
             {{all_on({a, b}, {dst})}}, {{a, {dst}, {}}, {b, {dst}, {}}}, {united(*named)}, lookalikes(*named));
      }
    }
  }

  void together() {
    for (const PlatformId src : f_.navigable) {
      const auto& here = f_.items_on.at(src);
      auto elsewhere = items_not_on({src});
      if (here.empty() || elsewhere.empty()) continue;
      Rng rng = rng_for(pname(src));
      for (std::size_t k = 0; k < kSamples; ++k) {
        const ObjectId a = here[rng.uniform_index(here.size())];
        const ObjectId b = elsewhere[rng.uniform_index(elsewhere.size())];
        const auto named = name_objects({a, b});
        if (!named) continue;
        emit({{"object", (*named)[0].words}, {"object2", (*named)[1].words}},
             {{{SetPredicate::Op::kTogether, {a, b}, {}, {}}}}, {{b, {src}, {}}}, {united(*named)}, lookalikes(*named));
      }
    }
  }

  void set_up() {
    for (const PlatformId dst : f_.navigable) {
      Rng rng = rng_for(pname(dst));
      std::map<std::string, std::vector<ObjectId>> cats;
      for (const ObjectId o : items_not_on({dst})) {
        cats[f_.category_of.at(o)].push_back(o);
        for (const std::string& word : g_.words_covering(f_.category_of.at(o))) cats[word].push_back(o);
      }
      if (cats.size() < 2) continue;
      std::vector<std::string> names;
      for (const auto& [c, objs] : cats) names.push_back(c);
      for (std::size_t k = 0; k < kSamples; ++k) {
        rng.shuffle(names);
        // "One cup next to one mug" is no pair a person can tell from any other.
        if (g_.called(names[0], names[1]) || g_.called(names[1], names[0])) continue;
        const auto& first = cats.at(names[0]);
        const auto& second = cats.at(names[1]);
        const ObjectId a = first[rng.uniform_index(first.size())];
        const ObjectId b = second[rng.uniform_index(second.size())];
        // "one cup next to one plate": any cup and any plate will do, so the goal says so.
        SetPredicate pair{SetPredicate::Op::kAnyPairNear, called(names[0]), {dst}, called(names[1])};
        emit({{"target", pname(dst)}, {"category", category_text(names[0])}, {"category2", category_text(names[1])}},
             {{pair}}, {{a, {dst}, {}}, {b, {dst}, a}}, {called(names[0]), called(names[1])});
      }
    }
  }

  void put_away() {
    for (const ObjectId f : f_.multilayer) {
      std::vector<PlatformId> inner;
      for (const PlatformId p : g_.objects[f].platforms) {
        const graph::Platform& pl = g_.platforms[p];
        if (pl.navigable && pl.interior) inner.push_back(p);
      }
      if (inner.empty()) continue;
      const std::set<PlatformId> own(g_.objects[f].platforms.begin(), g_.objects[f].platforms.end());
      auto pool = items_not_on(own);
      if (pool.empty()) continue;
      Rng rng = rng_for(g_.objects[f].name);
      for (std::size_t k = 0; k < kSamples; ++k) {
        const ObjectId a = pool[rng.uniform_index(pool.size())];
        const auto named = name_objects({a});
        if (!named) continue;
        emit({{"object", (*named)[0].words}, {"furniture", furniture_name(f)}}, {{all_on({a}, inner)}}, {{a, inner, {}}},
             {united(*named)}, lookalikes(*named));
      }
    }
  }

  void sort() {
    for (const PlatformId src : f_.navigable) {
      const auto cats = categories_on(src);
      for (std::size_t i = 0; i < cats.size(); ++i) {
        for (std::size_t j = i + 1; j < cats.size(); ++j) {
          const auto a = of_category_on(cats[i], src), b = of_category_on(cats[j], src);
          if (static_cast<int>(a.size() + b.size()) > max_moves()) continue;
          Rng rng = rng_for(pname(src) + "/" + cats[i] + "/" + cats[j]);
          const auto targets = shuffled_targets(rng, {src});
          if (targets.size() < 2) continue;
          const PlatformId t1 = targets[0], t2 = targets[1];
          std::vector<Move> moves;
          for (const ObjectId o : a) moves.push_back({o, {t1}, {}});
          for (const ObjectId o : b) moves.push_back({o, {t2}, {}});
          emit({{"source", pname(src)}, {"target", pname(t1)}, {"target2", pname(t2)},
                {"category", category_text(cats[i])}, {"categories", plural_text(cats[i])},
                {"category2", category_text(cats[j])}, {"categories2", plural_text(cats[j])}},
               {{all_on(a, {t1}), all_on(b, {t2})}}, moves, {called(cats[i], src), called(cats[j], src)});
        }
      }
    }
  }

  void move_layer() {
    for (const ObjectId f : f_.multilayer) {
      std::vector<PlatformId> layers;
      for (const PlatformId p : g_.objects[f].platforms) {
        if (g_.platforms[p].navigable) layers.push_back(p);
      }
      for (const PlatformId from : layers) {
        const auto& objs = f_.items_on.at(from);
        if (objs.empty() || static_cast<int>(objs.size()) > max_moves()) continue;
        std::vector<ObjectId> direct;
        for (const ObjectId o : objs) {
          if (s_.objects[o].parent == from) direct.push_back(o);
        }
        Rng rng = rng_for(pname(from));
        std::vector<PlatformId> others;
        for (const PlatformId p : layers) {
          if (p != from) others.push_back(p);
        }
        rng.shuffle(others);
        for (const PlatformId to : others) {
          std::vector<Move> moves;
          for (const ObjectId o : direct) moves.push_back({o, {to}, {}});
          if (emit({{"layer", pname(from)}, {"layer2", pname(to)}, {"furniture", furniture_name(f)},
                    {"count", std::to_string(objs.size())}},
                   {{all_on(objs, {to})}}, moves, {episode::pickable_on(g_, s_, from)})) {
            break;
          }
        }
      }
    }
  }

  void pair() {
    for (const PlatformId dst : f_.navigable) {
      const auto& here = f_.items_on.at(dst);
      auto elsewhere = items_not_on({dst});
      if (here.empty() || elsewhere.empty()) continue;
      Rng rng = rng_for(pname(dst));
      for (std::size_t k = 0; k < kSamples; ++k) {
        const ObjectId anchor = here[rng.uniform_index(here.size())];
        const ObjectId a = elsewhere[rng.uniform_index(elsewhere.size())];
        if (s_.objects[anchor].parent != dst) continue;  // needs its free spaces
        const auto named = name_objects({a, anchor});
        if (!named) continue;
        emit({{"object", (*named)[0].words}, {"object2", (*named)[1].words}},
             {{{SetPredicate::Op::kNear, {a, anchor}, {}, {}}}}, {{a, {dst}, anchor}}, {united(*named)},
             lookalikes(*named));
      }
    }
  }

  // What several named objects select together, and their look-alike records.
  static std::vector<ObjectId> united(const std::vector<NamedObject>& named) {
    std::vector<ObjectId> out;
    for (const NamedObject& n : named) out.insert(out.end(), n.selects.begin(), n.selects.end());
    return out;
  }
  static std::vector<Identification> lookalikes(const std::vector<NamedObject>& named) {
    std::vector<Identification> out;
    for (const NamedObject& n : named) out.insert(out.end(), n.lookalikes.begin(), n.lookalikes.end());
    return out;
  }

  const graph::SceneGraph& g_;
  const WorldState& s_;
  const TaskOptions& options_;
  const render::VisibilityOracle* seeing_;
  DropCounts& dropped_;
  episode::PlacementMemo* memo_;
  SceneFacts f_;
  const OutcomeTemplate* tmpl_ = nullptr;
  std::vector<OutcomeTask>* out_ = nullptr;
};

}  // namespace

const char* to_string(OutcomeKind kind) {
  for (const KindSpec& k : kinds()) {
    if (k.kind == kind) return k.name;
  }
  return "unknown";
}

std::vector<OutcomeTemplate> load_templates(const std::string& source) {
  nlohmann::json doc;
  std::string origin = source;
  if (source == "builtin") {
    doc = nlohmann::json::parse(kOutcomeTemplatesJson);
    origin = "built-in outcome templates";
  } else {
    doc = read_json_file(source);
  }
  const JsonField root(doc, origin);
  const JsonField list = root.at("templates");
  std::vector<OutcomeTemplate> out;
  std::set<std::string> ids;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const JsonField t = list.at(i);
    OutcomeTemplate tmpl{t.at("id").as_string(), t.at("family").as_string(), OutcomeKind::kGatherCategory,
                         t.at("text").as_string()};
    if (!ids.insert(tmpl.id).second) t.at("id").fail("duplicate template id '" + tmpl.id + "'");
    const std::string kind = t.at("kind").as_string();
    const KindSpec* spec = spec_named(kind);
    if (spec == nullptr) t.at("kind").fail("template " + tmpl.id + ": unknown kind '" + kind + "'");
    tmpl.kind = spec->kind;
    const auto used = placeholders_of(tmpl.text);
    for (const auto& ph : used) {
      if (spec->allowed.count(ph) == 0) {
        t.at("text").fail("template " + tmpl.id + ": unknown placeholder {" + ph + "} for kind " + kind);
      }
    }
    for (const auto& alternatives : spec->required) {
      const bool present = std::any_of(alternatives.begin(), alternatives.end(),
                                       [&](const std::string& ph) { return used.count(ph) != 0; });
      if (!present) {
        t.at("text").fail("template " + tmpl.id + ": missing placeholder {" + *alternatives.begin() + "}");
      }
    }
    out.push_back(std::move(tmpl));
  }
  return out;
}

std::vector<OutcomeTask> generate_outcomes(const graph::SceneGraph& g, const episode::WorldState& initial,
                                           const std::vector<OutcomeTemplate>& templates, const TaskOptions& options,
                                           std::vector<std::string>& warnings, DropCounts& dropped,
                                           episode::PlacementMemo* memo, const render::VisibilityOracle* seeing) {
  std::vector<OutcomeTask> all;
  Instantiator inst(g, initial, options, seeing, dropped, memo);
  for (const OutcomeTemplate& t : templates) inst.run(t, all);
  // One task per goal: the first template that produced it keeps it.
  std::vector<OutcomeTask> out;
  std::set<std::string> seen;
  for (OutcomeTask& t : all) {
    if (seen.insert(to_json(g, t.goal).dump()).second) out.push_back(std::move(t));
  }
  if (out.empty() && !templates.empty()) warnings.push_back("level 4: no template applies to scene " + g.scene);
  return out;
}

}  // namespace mtg::tasks
