#include "core/tasks/sequential.h"

#include <algorithm>
#include <set>

#include "core/util/hash.h"
#include "core/tasks/referring.h"
#include "core/util/rng.h"

namespace mtg::tasks {
namespace {

constexpr int kAttemptsPerChain = 25;

// Re-plans `task` for state `s`: the same goal, with keys valid now. nullopt if no longer feasible.
std::optional<AtomicTask> replan(const graph::SceneGraph& g, const episode::WorldState& s,
                                 const AtomicTask& task, const TaskOptions& options) {
  AtomicFilter filter{{task.goal.item}, {task.goal.platform}};
  for (AtomicTask& t : enumerate_atomic(g, s, options, filter)) {
    if (t.key == task.key) return std::move(t);
  }
  return std::nullopt;
}

}  // namespace

std::vector<Sequence> generate_sequences(const graph::SceneGraph& g, const episode::WorldState& initial,
                                         const std::vector<AtomicTask>& atomic, int count,
                                         const TaskOptions& options, std::vector<std::string>& warnings,
                                         DropCounts& dropped) {
  std::vector<Sequence> out;
  if (atomic.empty() || count <= 0) return out;
  std::set<std::string> seen;
  const int chain = std::max(2, options.level3_chain);
  int failures = 0;
  for (int n = 0; n < count; ++n) {
    bool made = false;
    for (int attempt = 0; attempt < kAttemptsPerChain && !made; ++attempt) {
      Rng rng(derive_seed(options.seed, fnv1a64("L3/" + std::to_string(n) + "/" + std::to_string(attempt))));
      Sequence seq;
      episode::WorldState s = initial;
      std::set<int> moved, changed;  // objects moved, platforms whose contents changed
      for (int part = 0; part < chain; ++part) {
        // A step must be worth asking and nameable where it starts (cheap tests, made before
        // any re-planning).
        auto wording = [&](const episode::AtomicGoal& goal) -> std::optional<Identified> {
          if (episode::goal_met_from_any_side(g, s, goal, options.goals)) {
            dropped.add("trivial", 3);
            return std::nullopt;
          }
          auto words = identify(g, s, goal, options.ambiguity, part);
          if (!words) dropped.add("unidentifiable", 3);
          return words;
        };
        std::optional<AtomicTask> next;
        std::optional<Identified> words;
        const bool chained = part > 0 && rng.uniform01() >= 0.5;
        if (chained) {
          // Something next to (or relative to) an object already moved.
          const int last_item = seq.parts.back().goal.item;
          const int platform = seq.parts.back().goal.platform;
          std::vector<int> items;
          for (const int p : g.navigable) {
            for (const int o : episode::pickable_on(g, s, p)) {
              if (moved.count(o) == 0) items.push_back(o);
            }
          }
          if (!items.empty()) {
            const int item = items[rng.uniform_index(items.size())];
            // An item the text could not name is not worth enumerating.
            if (refer(g, {&s}, item, episode::furniture_platform_of(g, s, item), options.ambiguity)) {
              std::vector<AtomicTask> options_here;
              for (AtomicTask& t : enumerate_atomic(g, s, options, AtomicFilter{{item}, {platform}})) {
                const auto anchors = t.goal.anchors();
                if (std::find(anchors.begin(), anchors.end(), last_item) != anchors.end()) {
                  options_here.push_back(std::move(t));
                }
              }
              if (!options_here.empty()) {
                next = options_here[rng.uniform_index(options_here.size())];
                words = wording(next->goal);
                if (!words) break;
              }
            }
          }
        }
        if (!next) {
          const AtomicTask& pick = atomic[rng.uniform_index(atomic.size())];
          if (moved.count(pick.goal.item) != 0) break;
          words = wording(pick.goal);  // re-planning keeps the goal
          if (!words) break;
          bool touched = changed.count(pick.goal.source) != 0 || changed.count(pick.goal.platform) != 0;
          for (const int a : pick.goal.anchors()) touched = touched || moved.count(a) != 0;
          next = touched ? replan(g, s, pick, options) : std::optional<AtomicTask>(pick);
          if (!next) break;
        }
        apply_effect(g, s, *next);
        next->placed_at = s.objects[static_cast<std::size_t>(next->goal.item)].position;
        next->margin = episode::goal_margin(g, s, next->goal, options.goals);
        seq.words.push_back(std::move(*words));
        moved.insert(next->goal.item);
        changed.insert(next->goal.source);
        changed.insert(next->goal.platform);
        seq.parts.push_back(std::move(*next));
      }
      if (static_cast<int>(seq.parts.size()) < chain) continue;  // a step could not be drawn
      // Every goal must still hold at the end, as robustly as when it was placed.
      bool ok = true, robust = true;
      for (AtomicTask& p : seq.parts) {
        p.margin = std::min(p.margin, episode::goal_margin(g, s, p.goal, options.goals));
        ok = ok && p.margin > 0.0;
        robust = robust && p.margin >= options.min_margin;
      }
      if (!ok) continue;
      if (!robust) {
        dropped.add("fragile", 3);
        continue;
      }
      std::string key;
      for (const AtomicTask& p : seq.parts) key += p.key + "|";
      if (!seen.insert(key).second) continue;
      out.push_back(std::move(seq));
      made = true;
    }
    if (!made) ++failures;
  }
  if (failures > 0) {
    warnings.push_back("level 3: " + std::to_string(failures) + " of " + std::to_string(count) +
                       " chains could not be drawn (duplicates or infeasible second steps after " +
                       std::to_string(kAttemptsPerChain) + " attempts each)");
  }
  return out;
}

}  // namespace mtg::tasks
