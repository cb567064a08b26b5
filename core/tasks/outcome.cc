#include "core/tasks/outcome.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>

#include "core/episode/placement.h"
#include "core/episode/rules.h"
#include "core/episode/state_change.h"
#include "core/tasks/identify.h"
#include "core/tasks/outcome_kinds.h"
#include "core/tasks/phrasing.h"
#include "core/tasks/referring.h"
#include "core/util/hash.h"
#include "core/util/rng.h"

namespace mtg::tasks {
namespace {

using episode::SetPredicate;
using episode::WorldState;

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

// Object-level placeholders are drawn this many times per platform-level binding (kinds that
// draw objects; the others take every binding their scene offers).
constexpr std::size_t kSamples = 100;
// Kinds whose bindings are fewer per platform (one object here, one elsewhere) draw more often.
constexpr std::size_t kManySamples = 300;
// Two objects to one of every platform: the most bindings of all.
constexpr std::size_t kFewSamples = 60;

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
    const int number = episode::number_on(g, s, from, m.object);
    if (number == 0) return std::nullopt;
    if (!play(graph::navigation_key(g.platforms[from].label)) || !play("o" + std::to_string(number))) {
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
      // "Anywhere" is the platform itself: its objects' free spaces are worked out only for a move
      // next to one of them.
      std::vector<episode::PlaceTarget> targets;
      if (m.next_to.valid()) {
        targets = episode::place_targets(g, s, to, static_cast<graph::Side>(s.side), rules.min_region_size, memo);
      } else {
        targets.push_back(episode::anywhere_target(dest));
      }
      for (const episode::PlaceTarget& t : targets) {
        const bool wanted = m.next_to.valid() ? t.anchor == m.next_to : t.key == episode::kAnywhereKey;
        if (!wanted) continue;
        // The step finds where the item goes (or that it does not fit): not worked out twice.
        const int steps = s.steps;
        placed = play(t.key);
        if (placed) break;
        s.steps = steps;  // a refused place is not counted: the plan is the one made without trying it
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

// Values with "{count}" bound where it counts two or more ("take all 1 things" reads wrong; the
// phrasings without it serve one item).
std::map<std::string, std::string> with_count(std::map<std::string, std::string> values, std::size_t n) {
  if (n >= 2) values["count"] = std::to_string(n);
  return values;
}

// "one", "two": a count as a text says it.
std::string number_word(int n) {
  static const char* words[] = {"no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten"};
  return n >= 0 && n <= 10 ? words[n] : std::to_string(n);
}

// "one book", "two books": a count of a noun as a text says it.
std::string counted(int n, const std::string& singular, const std::string& plural_words) {
  return number_word(n) + " " + (n == 1 ? singular : plural_words);
}

// "shelf_1", "shelf_1 and table_2", "shelf_1, table_2 and bed_0".
std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? " and " : ", ";
    out += names[i];
  }
  return out;
}

class Instantiator {
 public:
  Instantiator(const graph::SceneGraph& g, const WorldState& s, const TaskOptions& options,
               const render::VisibilityOracle* seeing, DropCounts& dropped,
               episode::PlacementMemo* memo)
      : g_(g), s_(s), options_(options), seeing_(seeing), dropped_(dropped), memo_(memo),
        f_(facts(g, s, options.ambiguity)) {}

  /// Every task of one kind, each worded by one of `phrasings` (all of that kind), chosen by its
  /// goal with the seed. Returns how many bindings reached the checks (a kind without any is
  /// stopped by its precondition).
  std::size_t run(OutcomeKind kind, const std::vector<const OutcomeTemplate*>& phrasings,
                  std::vector<OutcomeTask>& out) {
    kind_ = kind;
    phrasings_ = &phrasings;
    out_ = &out;
    candidates_ = 0;
    switch (kind) {
      case OutcomeKind::kGatherCategory: gather_category(); break;
      case OutcomeKind::kConsolidate: consolidate(); break;
      case OutcomeKind::kClearPlatform: clear_platform(); break;
      case OutcomeKind::kClearCategory: clear_category(); break;
      case OutcomeKind::kArrangeOn: arrange_on(); break;
      case OutcomeKind::kTogether: together(); break;
      case OutcomeKind::kSetUp: set_up(); break;
      case OutcomeKind::kPutAway: put_away(); break;
      case OutcomeKind::kSort: sort(); break;
      case OutcomeKind::kMoveLayer: move_layer(); break;
      case OutcomeKind::kPair: pair(); break;
      case OutcomeKind::kSwap: swap(); break;
      case OutcomeKind::kLeaveExactly: leave_count(false); break;
      case OutcomeKind::kThinOut: leave_count(true); break;
      case OutcomeKind::kBringSome: bring_some(); break;
      case OutcomeKind::kKeepOne: keep_one(); break;
      case OutcomeKind::kSplit: split(); break;
      case OutcomeKind::kSpreadOut: spread_out(); break;
      case OutcomeKind::kSeparate: separate(); break;
      case OutcomeKind::kJoinKind: join_kind(); break;
      case OutcomeKind::kGroupAround: group_around(); break;
      case OutcomeKind::kClearAround: clear_around(); break;
      case OutcomeKind::kTwoPairs: two_pairs(); break;
      case OutcomeKind::kMoveAll: move_all(); break;
      case OutcomeKind::kKeepOnly: keep_only(); break;
      case OutcomeKind::kLayOut: lay_out(); break;
      case OutcomeKind::kPutInside: put_inside(); break;
      case OutcomeKind::kBesideKind: beside_kind(); break;
      case OutcomeKind::kAllButOne: all_but_one(); break;
      case OutcomeKind::kFillEmpty: fill_empty(); break;
      case OutcomeKind::kGatherTwo: gather_two(); break;
    }
    return candidates_;
  }

 private:
  Rng rng_for(const std::string& binding) const {
    return Rng(derive_seed(options_.seed, fnv1a64(std::string("L4/") + to_string(kind_) + "/" + binding)));
  }
  std::string pname(PlatformId p) const { return g_.platforms[p].name; }
  // "books", "pairs of shoes": a category's plural as the text writes it.
  std::string plural_text(const std::string& cat) const {
    const auto it = f_.plural_of.find(cat);
    return it != f_.plural_of.end() ? it->second : plural(category_text(cat));
  }
  // Furniture by its instance name, as the platform names the agent reads spell it.
  std::string furniture_name(ObjectId f) const { return g_.objects[f].name; }

  // What category words select, read from the scene rather than from the goal: every item the
  // word names (its own noun, or one the word covers: "every bottle" takes in the spice jars) on
  // `platform` (at any depth), or anywhere in the scene for none.
  std::vector<ObjectId> called(const std::string& cat, PlatformId platform = {}) const {
    std::vector<ObjectId> out;
    auto named = [&](ObjectId o) { return g_.called(cat, category_key(g_.objects[o], options_.ambiguity)); };
    if (platform.valid()) {
      for (const ObjectId o : episode::pickable_on(g_, s_, platform)) {
        if (named(o)) out.push_back(o);
      }
      return out;
    }
    for (const ObjectId i : g_.objects.ids()) {
      if (g_.objects[i].pickable() && named(i)) out.push_back(i);
    }
    return out;
  }

  // How the text names one object, or why it cannot (occluded: named in the geometry, but not as
  // its platform's arrival view shows it).
  struct ObjectNaming {
    std::optional<NamedObject> named;
    bool occluded = false;
  };
  // Naming reads the arrival view, the same for every binding: once per object.
  const ObjectNaming& name_object(ObjectId o) {
    auto it = naming_.find(o);
    if (it == naming_.end()) it = naming_.emplace(o, name_fresh(o)).first;
    return it->second;
  }
  ObjectNaming name_fresh(ObjectId o) const {
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
      const ObjectNaming& naming = name_object(o);
      if (!naming.named) {
        dropped_.add(naming.occluded ? "occluded" : "unidentifiable", 4);
        return std::nullopt;
      }
      out.push_back(*naming.named);
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
  // Whether every object stands directly on `platform` (none on another item): a plan moves
  // them one by one.
  bool all_direct(const std::vector<ObjectId>& objs, PlatformId platform) const {
    return std::all_of(objs.begin(), objs.end(), [&](ObjectId o) { return s_.objects[o].parent == platform; });
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
  static std::vector<ObjectId> minus(std::vector<ObjectId> a, const std::vector<ObjectId>& b) {
    a.erase(std::remove_if(a.begin(), a.end(), [&](ObjectId o) { return std::find(b.begin(), b.end(), o) != b.end(); }),
            a.end());
    return a;
  }

  // Fills a phrasing, plans, verifies the goal with the judge's predicate, and keeps the task.
  // `selects` holds what the text's words pick out, one set per object list of the goal's
  // predicates (objects, then objects2 where used), computed from the words: the goal must ask
  // for exactly those objects, or the text would not say which ones it wants.
  bool emit(const std::map<std::string, std::string>& values, episode::OutcomeGoal goal,
            const std::vector<Move>& moves, const std::vector<std::vector<ObjectId>>& selects,
            std::vector<Identification> lookalikes = {}) {
    ++candidates_;
    // A goal already made (by this kind or an earlier one) is not made twice.
    std::string key = to_json(g_, goal).dump();
    if (made_.count(key) != 0) return false;
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
    auto plan = planned(moves);
    if (!plan || !episode::outcome_satisfied(g_, plan->after, goal, options_.goals)) return false;
    OutcomeTask task;
    // The phrasing is drawn by the goal, so the same goal reads the same however the kinds run,
    // among those whose every placeholder is bound (a kind leaves "{categories}" unbound for one
    // item: "all the canisters ... put them" said of one canister misleads).
    std::vector<const OutcomeTemplate*> usable;
    for (const OutcomeTemplate* t : *phrasings_) {
      const auto used = placeholders_of(t->text);
      if (std::all_of(used.begin(), used.end(), [&](const std::string& ph) { return values.count(ph) != 0; })) {
        usable.push_back(t);
      }
    }
    if (usable.empty()) return false;
    Rng pick(derive_seed(options_.seed, fnv1a64("L4 phrasing/" + key)));
    task.tmpl = usable[pick.uniform_index(usable.size())];
    task.text = task.tmpl->text;
    for (const auto& [name, value] : values) replace_all(task.text, "{" + name + "}", value);
    task.goal = std::move(goal);
    task.oracle = std::move(plan->keys);
    std::set<ObjectId> listed_objects;
    for (const SetPredicate& p : task.goal.all) listed_objects.insert(p.objects.begin(), p.objects.end());
    for (const ObjectId o : listed_objects) {
      const bool moved = episode::furniture_platform_of(g_, s_, o) != episode::furniture_platform_of(g_, plan->after, o);
      task.moved += moved ? 1 : 0;
    }
    task.identify = std::move(lookalikes);
    out_->push_back(std::move(task));
    made_.insert(std::move(key));
    return true;
  }

  // plan_moves from the initial state, each distinct first move (object, destinations, next-to)
  // played once: bindings share first moves (four in ten of all the moves planned are one
  // planned before), and the moves after it play on from the state it left, as in one plan.
  std::optional<Plan> planned(const std::vector<Move>& moves) {
    if (moves.empty()) return plan_moves(g_, s_, moves, options_, memo_);
    const Move& first = moves.front();
    std::string key = std::to_string(first.object.value()) + (first.next_to.valid() ? "@" + std::to_string(first.next_to.value()) : "");
    for (const PlatformId p : first.platforms) key += "," + std::to_string(p.value());
    auto it = first_moves_.find(key);
    if (it == first_moves_.end()) {
      std::optional<FirstMove> made;
      if (auto one = plan_moves(g_, s_, {first}, options_, memo_)) {
        made = FirstMove{std::move(one->keys), episode::change_between(s_, one->after)};
      }
      it = first_moves_.emplace(std::move(key), std::move(made)).first;
    }
    if (!it->second) return std::nullopt;
    WorldState s = s_;
    episode::apply_change(s, it->second->change);
    auto rest = plan_moves(g_, std::move(s), {moves.begin() + 1, moves.end()}, options_, memo_);
    if (!rest) return std::nullopt;
    rest->keys.insert(rest->keys.begin(), it->second->keys.begin(), it->second->keys.end());
    return rest;
  }

  bool all_seen(const std::vector<std::vector<ObjectId>>& selects) {
    if (seeing_ == nullptr) return true;
    for (const auto& list : selects) {
      for (const ObjectId o : list) {
        if (!seen(o)) return false;
      }
    }
    return true;
  }
  // Whether `o` shows clearly, its number readable, where the agent looks for it: every binding
  // asks of the same state, so once per object.
  bool seen(ObjectId o) {
    auto it = seen_.find(o);
    if (it == seen_.end()) {
      const PlatformId platform = episode::furniture_platform_of(g_, s_, o);
      bool shows = platform.valid();
      if (shows) {
        const auto sight = seeing_->arrival_view(s_, platform);
        shows = sight->clearly_visible(o) && seeing_->mark_readable(s_, platform, o);
      }
      it = seen_.emplace(o, shows).first;
    }
    return it->second;
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
        if (list == &p.objects2 && !episode::uses_objects2(p.op)) continue;
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
  static SetPredicate none_on(std::vector<ObjectId> objects, std::vector<PlatformId> platforms) {
    return {SetPredicate::Op::kNoneOn, std::move(objects), std::move(platforms), {}};
  }
  static SetPredicate count_on(std::vector<ObjectId> objects, std::vector<PlatformId> platforms, int min, int max) {
    return {SetPredicate::Op::kCountOn, std::move(objects), std::move(platforms), {}, min, max};
  }
  static SetPredicate with(SetPredicate::Op op, std::vector<ObjectId> objects, std::vector<ObjectId> objects2 = {}) {
    return {op, std::move(objects), {}, std::move(objects2)};
  }
  // Moves of each object to the first of `targets` that takes it.
  static std::vector<Move> moves_to(const std::vector<ObjectId>& objs, const std::vector<PlatformId>& targets) {
    std::vector<Move> out;
    for (const ObjectId o : objs) out.push_back({o, targets, {}});
    return out;
  }

  void gather_category() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        if (objs.size() < 2 || static_cast<int>(objs.size()) > max_moves()) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        try_targets(rng, {src}, [&](PlatformId dst) {
          return emit({{"source", pname(src)}, {"target", pname(dst)}, {"category", category_text(cat)},
                       {"categories", plural_text(cat)}, {"count", std::to_string(objs.size())}},
                      {{all_on(objs, {dst})}}, moves_to(objs, {dst}), {called(cat, src)});
        });
      }
    }
  }

  // Every item of a noun in the home; the text says where they stand, so a person can find them
  // all without searching every platform.
  void consolidate() {
    for (const auto& entry : f_.by_category) {
      // Named, not a structured binding: clang before 16 (scripts/fuzz's) cannot capture those.
      const auto& cat = entry.first;
      const auto& objs = entry.second;
      if (objs.size() < 2 || static_cast<int>(objs.size()) > max_moves()) continue;
      std::vector<std::string> sources;
      for (const PlatformId p : f_.navigable) {
        if (!of_category_on(cat, p).empty()) sources.push_back(pname(p));
      }
      if (sources.size() < 2) continue;  // from one platform it is gather_category
      Rng rng = rng_for(cat);
      try_targets(rng, {}, [&](PlatformId dst) {
        std::vector<Move> moves;
        for (const ObjectId o : objs) {
          if (episode::furniture_platform_of(g_, s_, o) != dst) moves.push_back({o, {dst}, {}});
        }
        return emit({{"target", pname(dst)}, {"category", category_text(cat)},
                     {"categories", plural_text(cat)}, {"count", std::to_string(objs.size())},
                     {"sources", listed(sources)}},
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
      emit(with_count({{"source", pname(src)}}, objs.size()), {{none_on(objs, {src})}},
           moves_to(direct, shuffled_targets(rng, {src})), {episode::pickable_on(g_, s_, src)});
    }
  }

  void clear_category() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        if (objs.size() == f_.items_on.at(src).size() || static_cast<int>(objs.size()) > max_moves()) continue;
        if (!all_direct(objs, src)) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        std::map<std::string, std::string> values = {{"source", pname(src)}, {"category", category_text(cat)}};
        if (objs.size() >= 2) {
          values["categories"] = plural_text(cat);
          values["count"] = std::to_string(objs.size());
        }
        emit(values, {{none_on(objs, {src})}}, moves_to(objs, shuffled_targets(rng, {src})), {called(cat, src)});
      }
    }
  }

  void arrange_on() {
    for (const PlatformId dst : f_.navigable) {
      const auto pool = items_not_on({dst});
      if (pool.size() < 2) continue;
      Rng rng = rng_for(pname(dst));
      for (std::size_t k = 0; k < kFewSamples; ++k) {
        const ObjectId a = pool[rng.uniform_index(pool.size())], b = pool[rng.uniform_index(pool.size())];
        if (a == b) continue;
        const auto named = name_objects({a, b});
        if (!named) continue;
        emit({{"object", (*named)[0].words}, {"object2", (*named)[1].words}, {"target", pname(dst)}},
             {{all_on({a, b}, {dst})}}, {{a, {dst}, {}}, {b, {dst}, {}}}, {united(*named)}, lookalikes(*named));
      }
    }
  }

  void together() {
    here_and_elsewhere([&](PlatformId src, ObjectId a, ObjectId b) {
      const auto named = name_objects({a, b});
      if (!named) return;
      emit({{"object", (*named)[0].words}, {"object2", (*named)[1].words}},
           {{with(SetPredicate::Op::kTogether, {a, b})}}, {{b, {src}, {}}}, {united(*named)}, lookalikes(*named));
    });
  }

  // Draws an item on each platform and one elsewhere, kManySamples times per platform.
  template <class Take>
  void here_and_elsewhere(Take take) {
    for (const PlatformId p : f_.navigable) {
      const auto& here = f_.items_on.at(p);
      const auto elsewhere = items_not_on({p});
      if (here.empty() || elsewhere.empty()) continue;
      Rng rng = rng_for(pname(p));
      for (std::size_t k = 0; k < kManySamples; ++k) {
        const ObjectId a = here[rng.uniform_index(here.size())];
        const ObjectId b = elsewhere[rng.uniform_index(elsewhere.size())];
        take(p, a, b);
      }
    }
  }


  // "A cup from shelf_1 next to a plate from table_2 on the counter": the text scopes each noun to
  // the platform it comes from, and any of those will do.
  void set_up() {
    for (const PlatformId dst : f_.navigable) {
      Rng rng = rng_for(pname(dst));
      std::vector<std::pair<PlatformId, std::string>> scoped;  // (source, noun) with items
      for (const PlatformId src : f_.navigable) {
        if (src == dst) continue;
        for (const std::string& cat : categories_on(src)) scoped.emplace_back(src, cat);
      }
      if (scoped.size() < 2) continue;
      for (std::size_t k = 0; k < kSamples; ++k) {
        const auto& [src1, cat1] = scoped[rng.uniform_index(scoped.size())];
        const auto& [src2, cat2] = scoped[rng.uniform_index(scoped.size())];
        // "One cup next to one mug" is no pair a person can tell from any other.
        if (g_.called(cat1, cat2) || g_.called(cat2, cat1)) continue;
        const auto first = called(cat1, src1), second = called(cat2, src2);
        const ObjectId a = first[rng.uniform_index(first.size())];
        const ObjectId b = second[rng.uniform_index(second.size())];
        SetPredicate pair{SetPredicate::Op::kAnyPairNear, first, {dst}, second};
        emit({{"target", pname(dst)}, {"category", category_text(cat1)}, {"category2", category_text(cat2)},
              {"source", pname(src1)}, {"source2", pname(src2)}},
             {{pair}}, {{a, {dst}, {}}, {b, {dst}, a}}, {first, second});
      }
    }
  }

  std::vector<PlatformId> inside_of(ObjectId f) const {
    std::vector<PlatformId> inner;
    for (const PlatformId p : g_.objects[f].platforms) {
      const graph::Platform& pl = g_.platforms[p];
      if (pl.navigable && pl.interior) inner.push_back(p);
    }
    return inner;
  }

  void put_away() {
    for (const ObjectId f : f_.multilayer) {
      const std::vector<PlatformId> inner = inside_of(f);
      if (inner.empty()) continue;
      const std::set<PlatformId> own(g_.objects[f].platforms.begin(), g_.objects[f].platforms.end());
      auto pool = items_not_on(own);
      if (pool.empty()) continue;
      Rng rng = rng_for(g_.objects[f].name);
      for (std::size_t k = 0; k < kManySamples; ++k) {
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
          if (g_.called(cats[i], cats[j]) || g_.called(cats[j], cats[i])) continue;  // "bottles" and "spice jars"
          const auto a = of_category_on(cats[i], src), b = of_category_on(cats[j], src);
          if (static_cast<int>(a.size() + b.size()) > max_moves() || !all_direct(a, src) || !all_direct(b, src)) continue;
          Rng rng = rng_for(pname(src) + "/" + cats[i] + "/" + cats[j]);
          const auto targets = shuffled_targets(rng, {src});
          if (targets.size() < 2) continue;
          const PlatformId t1 = targets[0], t2 = targets[1];
          std::vector<Move> moves = moves_to(a, {t1});
          for (const Move& m : moves_to(b, {t2})) moves.push_back(m);
          std::map<std::string, std::string> values = {{"source", pname(src)}, {"target", pname(t1)}, {"target2", pname(t2)},
                                                       {"category", category_text(cats[i])},
                                                       {"category2", category_text(cats[j])}};
          if (a.size() >= 2) values["categories"] = plural_text(cats[i]);
          if (b.size() >= 2) values["categories2"] = plural_text(cats[j]);
          emit(values, {{all_on(a, {t1}), all_on(b, {t2})}}, moves, {called(cats[i], src), called(cats[j], src)});
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
          if (emit(with_count({{"layer", pname(from)}, {"layer2", pname(to)}, {"furniture", furniture_name(f)}},
                              objs.size()),
                   {{all_on(objs, {to})}}, moves_to(direct, {to}), {episode::pickable_on(g_, s_, from)})) {
            break;
          }
        }
      }
    }
  }

  void pair() {
    here_and_elsewhere([&](PlatformId dst, ObjectId anchor, ObjectId a) {
      const auto named = name_objects({a, anchor});
      if (!named) return;
      emit({{"object", (*named)[0].words}, {"object2", (*named)[1].words}},
           {{with(SetPredicate::Op::kNear, {a, anchor})}}, {{a, {dst}, anchor}}, {united(*named)}, lookalikes(*named));
    });
  }


  // Each of two items goes where the other stood.
  void swap() {
    here_and_elsewhere([&](PlatformId p, ObjectId a, ObjectId b) {
      const PlatformId q = episode::furniture_platform_of(g_, s_, b);
      if (s_.objects[a].parent != p || s_.objects[b].parent != q) return;  // a stack moves as one
      const auto named = name_objects({a, b});
      if (!named) return;
      emit({{"object", (*named)[0].words}, {"object2", (*named)[1].words}}, {{all_on({a}, {q}), all_on({b}, {p})}},
           {{a, {q}, {}}, {b, {p}, {}}}, {(*named)[0].selects, (*named)[1].selects}, lookalikes(*named));
    });
  }


  // "Leave exactly two books on shelf_1" (count_on n..n), or with `at_most` "no more than two".
  void leave_count(bool at_most) {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        const int m = static_cast<int>(objs.size());
        if (m < 2 || !all_direct(objs, src)) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        const auto targets = shuffled_targets(rng, {src});
        for (int kept = std::max(1, m - max_moves()); kept < m; ++kept) {
          const std::vector<ObjectId> moved(objs.begin() + kept, objs.end());
          emit({{"source", pname(src)}, {"categories", plural_text(cat)},
                {"kept", counted(kept, category_text(cat), plural_text(cat))}},
               {{count_on(objs, {src}, at_most ? 0 : kept, kept)}}, moves_to(moved, targets), {called(cat, src)});
        }
      }
    }
  }

  // "Put two of the books from shelf_1 on the bed": exactly that many of them end there.
  void bring_some() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        const int m = static_cast<int>(objs.size());
        if (m < 2 || !all_direct(objs, src)) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        const int n = 1 + static_cast<int>(rng.uniform_index(static_cast<std::uint64_t>(std::min(m - 1, max_moves()))));
        const std::vector<ObjectId> moved(objs.begin(), objs.begin() + n);
        try_targets(rng, {src}, [&](PlatformId dst) {
          return emit({{"source", pname(src)}, {"target", pname(dst)}, {"categories", plural_text(cat)},
                       {"moved", number_word(n)}},
                      {{count_on(objs, {dst}, n, n)}}, moves_to(moved, {dst}), {called(cat, src)});
        });
      }
    }
  }

  // "Keep one book on shelf_1 and take the other books to the bed".
  void keep_one() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        const int m = static_cast<int>(objs.size());
        if (m < 3 || m - 1 > max_moves() || !all_direct(objs, src)) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        const std::vector<ObjectId> moved(objs.begin() + 1, objs.end());
        try_targets(rng, {src}, [&](PlatformId dst) {
          return emit({{"source", pname(src)}, {"target", pname(dst)}, {"category", category_text(cat)},
                       {"categories", plural_text(cat)}},
                      {{count_on(objs, {src}, 1, 1), count_on(objs, {dst}, m - 1, m - 1)}}, moves_to(moved, {dst}),
                      {called(cat, src), called(cat, src)});
        });
      }
    }
  }

  // "Split the books on shelf_1 between the bed and the desk": all leave, each target gets some.
  void split() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        const int m = static_cast<int>(objs.size());
        if (m < 2 || m > max_moves() || !all_direct(objs, src)) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        const auto targets = shuffled_targets(rng, {src});
        for (std::size_t k = 0; k + 1 < targets.size() && k < 4; k += 2) {
          const PlatformId t1 = targets[k], t2 = targets[k + 1];
          std::vector<Move> moves;
          for (int i = 0; i < m; ++i) moves.push_back({objs[static_cast<std::size_t>(i)], {i % 2 == 0 ? t1 : t2}, {}});
          if (emit({{"source", pname(src)}, {"target", pname(t1)}, {"target2", pname(t2)}, {"categories", plural_text(cat)}},
                   {{all_on(objs, {t1, t2}), count_on(objs, {t1}, 1, m), count_on(objs, {t2}, 1, m)}}, moves,
                   {called(cat, src), called(cat, src), called(cat, src)})) {
            break;
          }
        }
      }
    }
  }

  // "Spread the books from shelf_1 out: no two on one surface".
  void spread_out() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        const int m = static_cast<int>(objs.size());
        if (m < 2 || m - 1 > max_moves() || !all_direct(objs, src)) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        const auto targets = shuffled_targets(rng, {src});
        // Disjoint candidate targets per moved item, so no two can land together.
        std::vector<Move> moves;
        for (int i = 1; i < m; ++i) {
          std::vector<PlatformId> mine;
          for (std::size_t t = static_cast<std::size_t>(i - 1); t < targets.size(); t += static_cast<std::size_t>(m - 1)) {
            mine.push_back(targets[t]);
          }
          moves.push_back({objs[static_cast<std::size_t>(i)], mine, {}});
        }
        emit({{"source", pname(src)}, {"categories", plural_text(cat)}}, {{with(SetPredicate::Op::kApart, objs)}}, moves,
             {called(cat, src)});
      }
    }
  }

  // Two items standing on one platform end on different ones.
  void separate() {
    for (const PlatformId p : f_.navigable) {
      const auto& here = f_.items_on.at(p);
      if (here.size() < 2) continue;
      Rng rng = rng_for(pname(p));
      for (std::size_t k = 0; k < kSamples; ++k) {
        const ObjectId a = here[rng.uniform_index(here.size())];
        const ObjectId b = here[rng.uniform_index(here.size())];
        if (a == b || s_.objects[b].parent != p) continue;
        const auto named = name_objects({a, b});
        if (!named) continue;
        emit({{"object", (*named)[0].words}, {"object2", (*named)[1].words}},
             {{with(SetPredicate::Op::kApart, {a, b})}}, {{b, shuffled_targets(rng, {p}), {}}}, {united(*named)},
             lookalikes(*named));
      }
    }
  }

  // "Put the cup from the desk with the other cups on the counter".
  void join_kind() {
    for (const PlatformId dst : f_.navigable) {
      std::map<std::string, int> here;
      for (const ObjectId o : f_.items_on.at(dst)) here[f_.category_of.at(o)] += 1;
      std::vector<ObjectId> pool;
      for (const ObjectId o : items_not_on({dst})) {
        const auto it = here.find(f_.category_of.at(o));
        if (it != here.end() && it->second >= 2) pool.push_back(o);
      }
      if (pool.empty()) continue;
      Rng rng = rng_for(pname(dst));
      rng.shuffle(pool);
      for (std::size_t k = 0; k < pool.size() && k < kSamples; ++k) {
        const ObjectId a = pool[k];
        const std::string& cat = f_.category_of.at(a);
        if (called(cat, dst).size() < 2) continue;  // "the other cups" there, by the same words
        const auto named = name_objects({a});
        if (!named) continue;
        emit({{"object", (*named)[0].words}, {"categories", plural_text(cat)}, {"target", pname(dst)}},
             {{all_on({a}, {dst})}}, {{a, {dst}, {}}}, {united(*named)}, lookalikes(*named));
      }
    }
  }

  // "Put the books from shelf_1 next to the lamp on the desk".
  void group_around() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        const int m = static_cast<int>(objs.size());
        if (m < 2 || m > max_moves() || !all_direct(objs, src)) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        auto anchors = items_not_on({src});
        rng.shuffle(anchors);
        for (std::size_t k = 0; k < anchors.size() && k < 3; ++k) {
          const ObjectId anchor = anchors[k];
          if (g_.called(cat, f_.category_of.at(anchor))) continue;
          const PlatformId dst = episode::furniture_platform_of(g_, s_, anchor);
          const auto named = name_objects({anchor});
          if (!named) continue;
          std::vector<Move> moves;
          for (const ObjectId o : objs) moves.push_back({o, {dst}, anchor});
          if (emit({{"source", pname(src)}, {"categories", plural_text(cat)}, {"object", (*named)[0].words}},
                   {{with(SetPredicate::Op::kAllNear, objs, {anchor})}}, moves, {called(cat, src), united(*named)},
                   lookalikes(*named))) {
            break;
          }
        }
      }
    }
  }

  // What stands side by side with `anchor` on its platform, directly on it.
  std::vector<ObjectId> next_to(ObjectId anchor, PlatformId p) const {
    std::vector<ObjectId> out;
    for (const ObjectId o : f_.items_on.at(p)) {
      if (o != anchor && s_.objects[o].parent == p &&
          episode::footprint_gap(s_.objects[o].footprint, s_.objects[anchor].footprint) <= options_.goals.around_distance) {
        out.push_back(o);
      }
    }
    return out;
  }

  // "Clear the space around the lamp from the desk": what stands next to it goes elsewhere, the
  // lamp stays.
  void clear_around() {
    for (const PlatformId p : f_.navigable) {
      for (const ObjectId anchor : f_.items_on.at(p)) {
        if (s_.objects[anchor].parent != p) continue;
        const auto near = next_to(anchor, p);
        if (near.empty() || static_cast<int>(near.size()) > max_moves()) continue;
        const auto named = name_objects({anchor});
        if (!named) continue;
        Rng rng = rng_for(g_.objects[anchor].name);
        emit({{"object", (*named)[0].words}},
             {{with(SetPredicate::Op::kNoneNear, near, {anchor}), all_on({anchor}, {p})}},
             moves_to(near, shuffled_targets(rng, {p})), {near, united(*named), united(*named)}, lookalikes(*named));
      }
    }
  }

  // Two "next to" pairs at once.
  void two_pairs() {
    const auto pool = items_not_on({});
    if (pool.size() < 4) return;
    for (const PlatformId p : f_.navigable) {
      const auto& here = f_.items_on.at(p);
      if (here.empty()) continue;
      Rng rng = rng_for(pname(p));
      for (std::size_t k = 0; k < kManySamples; ++k) {
        const ObjectId b = here[rng.uniform_index(here.size())];
        const ObjectId a = pool[rng.uniform_index(pool.size())];
        const ObjectId d = pool[rng.uniform_index(pool.size())];
        const ObjectId c = pool[rng.uniform_index(pool.size())];
        const std::set<ObjectId> distinct{a, b, c, d};
        if (distinct.size() < 4) continue;
        const PlatformId pa = episode::furniture_platform_of(g_, s_, a), pc = episode::furniture_platform_of(g_, s_, c),
                         pd = episode::furniture_platform_of(g_, s_, d);
        if (pa == p || pc == pd) continue;
        const auto named = name_objects({a, b, c, d});
        if (!named) continue;
        emit({{"object", (*named)[0].words}, {"object2", (*named)[1].words}, {"object3", (*named)[2].words},
              {"object4", (*named)[3].words}},
             {{with(SetPredicate::Op::kNear, {a, b}), with(SetPredicate::Op::kNear, {c, d})}},
             {{a, {p}, b}, {c, {pd}, d}},
             {united({(*named)[0], (*named)[1]}), united({(*named)[2], (*named)[3]})}, lookalikes(*named));
      }
    }
  }

  // "Move everything on shelf_1 onto the bed".
  void move_all() {
    for (const PlatformId src : f_.navigable) {
      const auto& objs = f_.items_on.at(src);
      if (objs.empty() || static_cast<int>(objs.size()) > max_moves() || !all_direct(objs, src)) continue;
      Rng rng = rng_for(pname(src));
      try_targets(rng, {src}, [&](PlatformId dst) {
        return emit(with_count({{"source", pname(src)}, {"target", pname(dst)}}, objs.size()),
                    {{all_on(objs, {dst})}}, moves_to(objs, {dst}), {episode::pickable_on(g_, s_, src)});
      });
    }
  }

  // "Leave only the books on shelf_1": the rest goes, the books stay.
  void keep_only() {
    for (const PlatformId src : f_.navigable) {
      const auto& all = f_.items_on.at(src);
      if (!all_direct(all, src)) continue;
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        const auto others = minus(all, objs);
        if (objs.size() < 2 || others.empty() || static_cast<int>(others.size()) > max_moves()) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        emit({{"source", pname(src)}, {"categories", plural_text(cat)}},
             {{none_on(others, {src}), all_on(objs, {src})}}, moves_to(others, shuffled_targets(rng, {src})),
             {minus(episode::pickable_on(g_, s_, src), called(cat, src)), called(cat, src)});
      }
    }
  }

  // "Put a cup from shelf_1, a plate from the counter and a bowl from the desk on the table".
  void lay_out() {
    for (const PlatformId dst : f_.navigable) {
      std::vector<std::pair<PlatformId, std::string>> scoped;
      for (const PlatformId src : f_.navigable) {
        if (src == dst) continue;
        for (const std::string& cat : categories_on(src)) scoped.emplace_back(src, cat);
      }
      if (scoped.size() < 3) continue;
      Rng rng = rng_for(pname(dst));
      for (std::size_t k = 0; k < kSamples; ++k) {
        std::vector<std::pair<PlatformId, std::string>> three;
        for (int i = 0; i < 3; ++i) three.push_back(scoped[rng.uniform_index(scoped.size())]);
        bool distinct = true;
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) {
            if (i != j && g_.called(three[static_cast<std::size_t>(i)].second, three[static_cast<std::size_t>(j)].second)) {
              distinct = false;
            }
          }
        }
        if (!distinct) continue;
        std::vector<std::vector<ObjectId>> groups;
        std::vector<Move> moves;
        std::vector<SetPredicate> preds;
        for (const auto& [src, cat] : three) {
          groups.push_back(called(cat, src));
          moves.push_back({groups.back()[rng.uniform_index(groups.back().size())], {dst}, {}});
          preds.push_back(count_on(groups.back(), {dst}, 1, static_cast<int>(groups.back().size())));
        }
        emit({{"target", pname(dst)}, {"category", category_text(three[0].second)},
              {"category2", category_text(three[1].second)}, {"category3", category_text(three[2].second)},
              {"source", pname(three[0].first)}, {"source2", pname(three[1].first)}, {"source3", pname(three[2].first)}},
             {preds}, moves, groups);
      }
    }
  }

  // "Put the books from the desk inside cabinet_2" (any of its inside layers).
  void put_inside() {
    std::vector<ObjectId> furniture;
    for (const ObjectId i : g_.objects.ids()) {
      if (!inside_of(i).empty()) furniture.push_back(i);
    }
    for (const ObjectId f : furniture) {
      const std::vector<PlatformId> inner = inside_of(f);
      const std::set<PlatformId> own(g_.objects[f].platforms.begin(), g_.objects[f].platforms.end());
      Rng rng = rng_for(g_.objects[f].name);
      std::vector<std::pair<PlatformId, std::string>> scoped;
      for (const PlatformId src : f_.navigable) {
        if (own.count(src) != 0) continue;
        for (const std::string& cat : categories_on(src)) {
          const auto objs = of_category_on(cat, src);
          if (objs.size() >= 2 && static_cast<int>(objs.size()) <= max_moves() && all_direct(objs, src)) {
            scoped.emplace_back(src, cat);
          }
        }
      }
      rng.shuffle(scoped);
      for (std::size_t k = 0; k < scoped.size() && k < kSamples; ++k) {
        const auto& [src, cat] = scoped[k];
        const auto objs = of_category_on(cat, src);
        emit({{"source", pname(src)}, {"categories", plural_text(cat)}, {"furniture", furniture_name(f)}},
             {{all_on(objs, inner)}}, moves_to(objs, inner), {called(cat, src)});
      }
    }
  }

  // "Put the cup from the desk next to a plate on the counter" (any of them).
  void beside_kind() {
    for (const PlatformId dst : f_.navigable) {
      const auto cats = categories_on(dst);
      auto pool = items_not_on({dst});
      if (cats.empty() || pool.empty()) continue;
      Rng rng = rng_for(pname(dst));
      for (std::size_t k = 0; k < kManySamples; ++k) {
        const ObjectId a = pool[rng.uniform_index(pool.size())];
        const std::string& cat = cats[rng.uniform_index(cats.size())];
        if (g_.called(cat, f_.category_of.at(a)) || g_.called(f_.category_of.at(a), cat)) continue;
        const auto group = called(cat, dst);
        const auto named = name_objects({a});
        if (!named) continue;
        emit({{"object", (*named)[0].words}, {"category", category_text(cat)}, {"target", pname(dst)}},
             {{SetPredicate{SetPredicate::Op::kAnyPairNear, {a}, {dst}, group}}}, {{a, {dst}, group.front()}},
             {united(*named), group}, lookalikes(*named));
      }
    }
  }

  // "Take every book off shelf_1 except the leftmost book".
  void all_but_one() {
    for (const PlatformId src : f_.navigable) {
      for (const std::string& cat : categories_on(src)) {
        const auto objs = of_category_on(cat, src);
        const int m = static_cast<int>(objs.size());
        if (m < 2 || m - 1 > max_moves() || !all_direct(objs, src)) continue;
        Rng rng = rng_for(pname(src) + "/" + cat);
        const ObjectId keep = objs[rng.uniform_index(objs.size())];
        const auto named = name_objects({keep});
        if (!named) continue;
        const auto others = minus(objs, {keep});
        emit({{"source", pname(src)}, {"category", category_text(cat)}, {"categories", plural_text(cat)},
              {"object", (*named)[0].words}},
             {{none_on(others, {src}), all_on({keep}, {src})}}, moves_to(others, shuffled_targets(rng, {src})),
             {minus(called(cat, src), (*named)[0].selects), united(*named)}, lookalikes(*named));
      }
    }
  }

  // "Put two of the things on the desk onto the empty stool".
  void fill_empty() {
    std::vector<PlatformId> empty;
    for (const PlatformId p : f_.navigable) {
      if (episode::everything_on(g_, s_, p).empty()) empty.push_back(p);
    }
    if (empty.empty()) return;
    for (const PlatformId src : f_.navigable) {
      const auto& objs = f_.items_on.at(src);
      if (objs.size() < 3 || !all_direct(objs, src)) continue;
      Rng rng = rng_for(pname(src));
      const int n = 1 + static_cast<int>(rng.uniform_index(2));
      std::vector<PlatformId> targets = empty;
      rng.shuffle(targets);
      for (std::size_t k = 0; k < targets.size() && k < 3; ++k) {
        const PlatformId dst = targets[k];
        const std::vector<ObjectId> moved(objs.begin(), objs.begin() + n);
        if (emit({{"source", pname(src)}, {"target", pname(dst)}, {"moved", n == 1 ? "one of the things" : "two of the things"}},
                 {{count_on(objs, {dst}, n, n)}}, moves_to(moved, {dst}), {episode::pickable_on(g_, s_, src)})) {
          break;
        }
      }
    }
  }

  // "Bring the books from shelf_1 and the desk to the bed".
  void gather_two() {
    for (const PlatformId a : f_.navigable) {
      for (const std::string& cat : categories_on(a)) {
        for (const PlatformId b : f_.navigable) {
          if (!(a < b)) continue;
          const auto here = of_category_on(cat, a), there = of_category_on(cat, b);
          if (there.empty() || static_cast<int>(here.size() + there.size()) > max_moves()) continue;
          if (!all_direct(here, a) || !all_direct(there, b)) continue;
          std::vector<ObjectId> objs = here;
          objs.insert(objs.end(), there.begin(), there.end());
          std::vector<ObjectId> words = called(cat, a);
          for (const ObjectId o : called(cat, b)) words.push_back(o);
          Rng rng = rng_for(pname(a) + "/" + pname(b) + "/" + cat);
          try_targets(rng, {a, b}, [&](PlatformId dst) {
            return emit({{"source", pname(a)}, {"source2", pname(b)}, {"target", pname(dst)}, {"categories", plural_text(cat)}},
                        {{all_on(objs, {dst})}}, moves_to(objs, {dst}), {words});
          });
        }
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
  OutcomeKind kind_ = OutcomeKind::kGatherCategory;
  const std::vector<const OutcomeTemplate*>* phrasings_ = nullptr;
  std::vector<OutcomeTask>* out_ = nullptr;
  std::size_t candidates_ = 0;
  std::map<ObjectId, ObjectNaming> naming_;
  std::map<ObjectId, bool> seen_;
  struct FirstMove {
    std::vector<std::string> keys;
    episode::StateChange change;  // from the initial state
  };
  std::map<std::string, std::optional<FirstMove>> first_moves_;  // by object, next-to and platforms; none: it fails
  std::set<std::string> made_;  // goals kept so far (their JSON)
};

// No kind above `share` of the tasks: the largest kinds are cut to the greatest cap C for which
// sum(min(size, C)) * share >= C, keeping a seeded choice of each in its order.
std::vector<OutcomeTask> balance_kinds(std::vector<OutcomeTask> tasks, double share, std::uint64_t seed) {
  if (share <= 0.0 || share >= 1.0 || tasks.empty()) return tasks;
  std::map<OutcomeKind, std::vector<std::size_t>> of_kind;
  for (std::size_t i = 0; i < tasks.size(); ++i) of_kind[tasks[i].tmpl->kind].push_back(i);
  auto kept_with = [&](std::size_t cap) {
    std::size_t n = 0;
    for (const auto& entry : of_kind) n += std::min(entry.second.size(), cap);
    return n;
  };
  std::size_t cap = 0;
  for (const auto& entry : of_kind) cap = std::max(cap, entry.second.size());
  while (cap > 0 && static_cast<double>(cap) > share * static_cast<double>(kept_with(cap))) --cap;
  std::vector<bool> keep(tasks.size(), true);
  for (const auto& [kind, indices] : of_kind) {
    if (indices.size() <= cap) continue;
    std::vector<std::size_t> order = indices;
    Rng rng(derive_seed(seed, fnv1a64(std::string("L4 balance/") + to_string(kind))));
    rng.shuffle(order);
    for (std::size_t k = cap; k < order.size(); ++k) keep[order[k]] = false;
  }
  std::vector<OutcomeTask> out;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    if (keep[i]) out.push_back(std::move(tasks[i]));
  }
  return out;
}

}  // namespace

std::vector<OutcomeTask> generate_outcomes(const graph::SceneGraph& g, const episode::WorldState& initial,
                                           const std::vector<OutcomeTemplate>& templates, const TaskOptions& options,
                                           std::vector<std::string>& warnings, DropCounts& dropped,
                                           episode::PlacementMemo* memo, const render::VisibilityOracle* seeing) {
  // Each kind runs once, in the order its first template comes; every binding is worded by one of
  // the kind's phrasings (so adding phrasings adds wording, not work).
  std::vector<std::pair<OutcomeKind, std::vector<const OutcomeTemplate*>>> by_kind;
  for (const OutcomeTemplate& t : templates) {
    auto it = std::find_if(by_kind.begin(), by_kind.end(), [&](const auto& k) { return k.first == t.kind; });
    if (it == by_kind.end()) it = by_kind.insert(by_kind.end(), {t.kind, {}});
    it->second.push_back(&t);
  }
  std::vector<OutcomeTask> all;
  Instantiator inst(g, initial, options, seeing, dropped, memo);
  for (const auto& [kind, phrasings] : by_kind) {
    const std::size_t before = all.size();
    const std::size_t candidates = inst.run(kind, phrasings, all);
    if (all.size() == before) {
      const KindSpec& spec = *spec_named(to_string(kind));
      warnings.push_back("level 4: no " + std::string(spec.name) + " task on " + g.scene +
                         (candidates == 0 ? ": it needs " + std::string(spec.needs)
                                          : ": its " + std::to_string(candidates) + " candidate" + (candidates == 1 ? " was" : "s were") +
                                                " dropped (see the drop counts)"));
    }
  }
  // One task per goal (the instantiator keeps the first that made it).
  std::vector<OutcomeTask> out = std::move(all);
  if (out.empty() && !templates.empty()) warnings.push_back("level 4: no template applies to scene " + g.scene);
  return balance_kinds(std::move(out), options.level4_max_kind_share, options.seed);
}

}  // namespace mtg::tasks
