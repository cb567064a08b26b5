#include "core/tasks/sequential.h"

#include <algorithm>
#include <future>
#include <set>

#include "core/tasks/reference_memo.h"
#include "core/util/hash.h"
#include "core/util/parallel.h"
#include "core/util/rng.h"

namespace mtg::tasks {
namespace {

constexpr int kAttemptsPerChain = 100;

// Re-plans `task` for state `s`: the same goal, with keys valid now. nullopt if no longer feasible.
std::optional<AtomicTask> replan(const graph::SceneGraph& g, const episode::WorldState& s,
                                 const AtomicTask& task, const TaskOptions& options, episode::PlacementMemo* memo) {
  // A goal relative to an object has that object among its anchors: the rest need no look.
  AtomicFilter filter{{task.goal.item}, {task.goal.platform}, task.key, task.goal.anchor};
  auto found = enumerate_atomic(g, s, options, filter, nullptr, 1, memo);
  if (found.empty()) return std::nullopt;
  return std::move(found.front());
}

// Chain n as the attempts from `from` on draw it: the first that gives a valid chain (which may
// still duplicate another chain; the caller decides), with what its attempts dropped.
struct Drawn {
  std::optional<Sequence> sequence;
  std::string key;   // the parts' keys: identity for de-duplication
  int attempt = 0;   // the attempt that gave it
  DropCounts dropped;
};

Drawn draw_chain(const graph::SceneGraph& g, const episode::WorldState& initial, const std::vector<AtomicTask>& atomic,
                 int n, int from, const TaskOptions& options, const ReferenceMemo& references,
                 episode::PlacementMemo* memo) {
  Drawn drawn;
  const int chain = std::max(2, options.level3_chain);
  for (int attempt = from; attempt < kAttemptsPerChain; ++attempt) {
    Rng rng(derive_seed(options.seed, fnv1a64("L3/" + std::to_string(n) + "/" + std::to_string(attempt))));
    Sequence seq;
    episode::WorldState s = initial;
    std::set<graph::ObjectId> moved;     // objects moved
    std::set<graph::PlatformId> changed;  // platforms whose contents changed
    for (int part = 0; part < chain; ++part) {
      // A step must be worth asking and nameable where it starts (cheap tests, made before
      // any re-planning).
      auto wording = [&](const episode::AtomicGoal& goal) -> std::optional<Identified> {
        if (episode::goal_met_from_any_side(g, s, goal, options.goals)) {
          drawn.dropped.add("trivial", 3);
          return std::nullopt;
        }
        Naming words = identify(g, s, goal, options.ambiguity, part, &references, references.seeing());
        if (!words) drawn.dropped.add(words.occluded ? "occluded" : "unidentifiable", 3);
        return std::move(words.identified);
      };
      std::optional<AtomicTask> next;
      std::optional<Identified> words;
      const bool chained = part > 0 && rng.uniform01() >= 0.5;
      if (chained) {
        // Something next to (or relative to) an object already moved.
        const graph::ObjectId last_item = seq.parts.back().goal.item;
        const graph::PlatformId platform = seq.parts.back().goal.platform;
        std::vector<graph::ObjectId> items;
        for (const graph::PlatformId p : g.navigable) {
          for (const graph::ObjectId o : episode::pickable_on(g, s, p)) {
            if (moved.count(o) == 0) items.push_back(o);
          }
        }
        if (!items.empty()) {
          const graph::ObjectId item = items[rng.uniform_index(items.size())];
          // An item the text could not name is not worth enumerating.
          if (references.refer(s, item, episode::furniture_platform_of(g, s, item), {})) {
            const std::vector<AtomicTask> options_here =
                enumerate_atomic(g, s, options, AtomicFilter{{item}, {platform}, "", last_item}, nullptr, 1, memo);
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
        for (const graph::ObjectId a : pick.goal.anchors()) touched = touched || moved.count(a) != 0;
        next = touched ? replan(g, s, pick, options, memo) : std::optional<AtomicTask>(pick);
        if (!next) break;
      }
      apply_effect(g, s, *next);
      next->placed_at = s.objects[next->goal.item].position;
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
      drawn.dropped.add("fragile", 3);
      continue;
    }
    drawn.key.clear();
    for (const AtomicTask& p : seq.parts) drawn.key += p.key + "|";
    drawn.sequence = std::move(seq);
    drawn.attempt = attempt;
    return drawn;
  }
  return drawn;
}

}  // namespace

void generate_sequences(const graph::SceneGraph& g, const episode::WorldState& initial,
                        const std::vector<AtomicTask>& atomic, int count, const TaskOptions& options,
                        std::vector<std::string>& warnings, DropCounts& dropped, int jobs, const SequenceSink& take,
                        episode::PlacementMemo* memo, const render::VisibilityOracle* seeing) {
  if (atomic.empty() || count <= 0) return;
  // Each chain's attempts depend only on its number, so chains are drawn in parallel, a block at
  // a time; taking them in order, with a duplicate drawn on from its next attempt, gives the
  // one-thread result. With threads to spare, the next block is drawn while this thread takes
  // the last one in order, so no core waits on that serial part.
  constexpr int kBlock = 2048;
  const ReferenceMemo references(g, initial, options.ambiguity, seeing);  // every chain starts from `initial`
  std::set<std::string> seen;
  int failures = 0;
  const auto draw_block = [&](int from) {
    std::vector<Drawn> block(static_cast<std::size_t>(std::min(kBlock, count - from)));
    parallel_for(block.size(), jobs, [&](std::size_t k) {
      block[k] = draw_chain(g, initial, atomic, from + static_cast<int>(k), 0, options, references, memo);
    });
    return block;
  };
  std::future<std::vector<Drawn>> next;  // after what it reads: waited for before they go
  for (int from = 0; from < count; from += kBlock) {
    std::vector<Drawn> first = next.valid() ? next.get() : draw_block(from);
    if (jobs > 1 && from + kBlock < count) next = std::async(std::launch::async, draw_block, from + kBlock);
    for (std::size_t k = 0; k < first.size(); ++k) {
      const int n = from + static_cast<int>(k);
      Drawn drawn = std::move(first[k]);
      dropped.merge(drawn.dropped);
      while (drawn.sequence && !seen.insert(drawn.key).second) {
        drawn = draw_chain(g, initial, atomic, n, drawn.attempt + 1, options, references, memo);
        dropped.merge(drawn.dropped);
      }
      if (drawn.sequence) {
        take(std::move(*drawn.sequence));
      } else {
        ++failures;
      }
    }
  }
  if (failures > 0) {
    warnings.push_back("level 3: " + std::to_string(failures) + " of " + std::to_string(count) +
                       " chains could not be drawn (duplicates or infeasible second steps after " +
                       std::to_string(kAttemptsPerChain) + " attempts each)");
  }
}

}  // namespace mtg::tasks
