#include "core/tasks/generator.h"

#include <algorithm>
#include <cstdio>
#include <future>
#include <map>
#include <sstream>
#include <utility>

#include "core/episode/placement.h"
#include "core/episode/world_state.h"
#include "core/tasks/atomic.h"
#include "core/tasks/coverage.h"
#include "core/tasks/identify.h"
#include "core/tasks/outcome.h"
#include "core/tasks/phrasing.h"
#include "core/tasks/sequential.h"
#include "core/util/error.h"

namespace mtg::tasks {
namespace {

std::string task_id(const std::string& scene, int level, std::size_t index) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "/L%d/%06zu", level, index);
  return scene + buf;
}

// Denormalised columns of an atomic goal.
void fill_columns(const graph::SceneGraph& g, const episode::AtomicGoal& goal, Task& t) {
  t.item = g.objects[goal.item].name;
  t.source = g.platforms[goal.source].name;
  t.destination = g.platforms[goal.platform].name;
  for (const graph::ObjectId a : goal.anchors()) t.anchors.push_back(g.objects[a].name);
  if (goal.direction >= 0) t.direction = graph::direction_name(goal.direction);
}

// Where the oracle puts an atomic part's item (Task::placements).
OraclePlacement placement_of(const graph::SceneGraph& g, int part, const AtomicTask& a) {
  return {part, g.objects[a.goal.item].name, g.platforms[a.goal.platform].name, a.placed_at, a.margin};
}

}  // namespace

std::set<int> parse_levels(const std::string& text) {
  std::set<int> levels;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    if (part == "1" || part == "2" || part == "3" || part == "4") {
      levels.insert(part[0] - '0');
    } else {
      throw Error("unknown level '" + part + "' (levels are 1, 2, 3, 4)");
    }
  }
  if (levels.empty()) throw Error("no level given (use e.g. --levels 1,2,3,4)");
  return levels;
}

std::string describe_scene(const graph::SceneGraph& g) {
  const episode::WorldState s = episode::initial_state(g);
  std::string out;
  for (std::size_t k = 0; k < g.navigable.size(); ++k) {
    const graph::PlatformId p = g.navigable[k];
    out += "\n- platform l" + std::to_string(k + 1) + " " + g.platforms[p].name + ":";
    const auto& objects = episode::objects_on(s, p);
    if (objects.empty()) out += " empty";
    for (std::size_t i = 0; i < objects.size(); ++i) {
      out += std::string(i ? ", " : " ") + episode::listed_name(g.objects[objects[i]]);
    }
  }
  return out;
}

namespace {

// Task ids count per level in the order tasks are accepted: "<scene>/L<level>/<index>". With a
// sink, the tasks go to it a batch at a time instead of staying in the set.
class TaskNumbering {
 public:
  TaskNumbering(std::string scene, const TaskSink& sink) : scene_(std::move(scene)), sink_(sink) {}
  void add(Task t, TaskSet& set) {
    t.scene = scene_;
    t.id = task_id(scene_, t.level, next_[t.level]++);
    set.tasks.push_back(std::move(t));
    if (sink_ && set.tasks.size() >= kBatch) flush(set);
  }
  void flush(TaskSet& set) {
    if (sink_ && !set.tasks.empty()) sink_(std::exchange(set.tasks, {}));
  }
  std::size_t peek(int level) { return next_[level]; }
  void skip(int level) { ++next_[level]; }

 private:
  static constexpr std::size_t kBatch = 1024;
  std::string scene_;
  const TaskSink& sink_;
  std::map<int, std::size_t> next_;
};

// Levels 1 and 2: each atomic task, named in the initial state; Level 2 when it has look-alikes.
void add_atomic_tasks(const graph::SceneGraph& g, const episode::WorldState& initial,
                      const std::vector<AtomicTask>& atomic, const TaskOptions& options, TaskNumbering& numbering,
                      TaskSet& set, const render::VisibilityOracle* seeing) {
  // Every atomic task is named in the initial state.
  const ReferenceMemo memo(g, initial, options.ambiguity, seeing);
  for (const AtomicTask& a : atomic) {
    const Naming words = identify(g, initial, a.goal, options.ambiguity, 0, &memo, seeing);
    if (!words) {
      if (words.occluded) {
        set.dropped.add("occluded", has_lookalikes(g, initial, a.goal, options.ambiguity) ? 2 : 1);
      } else {
        set.dropped.add("unidentifiable", 2);
      }
      continue;
    }
    const int level = words->lookalikes.empty() ? 1 : 2;
    if (options.levels.count(level) == 0) continue;
    Task t;
    t.level = level;
    t.type = episode::to_string(a.goal.type);
    t.text = atomic_text(g, a.goal, words->wording, options.seed);
    fill_columns(g, a.goal, t);
    t.goal = {{"atomic", to_json(g, a.goal)}};
    t.identify = words->lookalikes;
    t.placements.push_back(placement_of(g, 0, a));
    t.oracle = a.oracle;
    t.oracle.push_back("0");
    t.step_limit = options.rules.step_limit;
    numbering.add(std::move(t), set);
  }
}

// A Level 3 task: a chain of atomic tasks, each part named in the state it starts from.
Task sequence_task(const graph::SceneGraph& g, const Sequence& seq, const TaskOptions& options) {
  Task t;
  t.level = 3;
  t.type = "sequence";
  std::vector<std::string> texts;
  nlohmann::json parts = nlohmann::json::array();
  for (std::size_t k = 0; k < seq.parts.size(); ++k) {
    const AtomicTask& p = seq.parts[k];
    texts.push_back(atomic_text(g, p.goal, seq.words[k].wording, options.seed));
    parts.push_back(to_json(g, p.goal));
    t.identify.insert(t.identify.end(), seq.words[k].lookalikes.begin(), seq.words[k].lookalikes.end());
    t.placements.push_back(placement_of(g, static_cast<int>(k), p));
    t.oracle.insert(t.oracle.end(), p.oracle.begin(), p.oracle.end());
  }
  t.text = sequence_text(texts);
  fill_columns(g, seq.parts.front().goal, t);
  t.goal = {{"sequence", parts}};
  t.oracle.push_back("0");
  t.step_limit = std::max(options.rules.step_limit, static_cast<int>(t.oracle.size()) + 4);
  return t;
}

// Level 3: each chain becomes a task as it is drawn.
void add_sequence_tasks(const graph::SceneGraph& g, const episode::WorldState& initial,
                        const std::vector<AtomicTask>& atomic, const TaskOptions& options, TaskNumbering& numbering,
                        TaskSet& set, int jobs, episode::PlacementMemo& memo, const render::VisibilityOracle* seeing) {
  generate_sequences(
      g, initial, atomic, options.level3_count, options, set.warnings, set.dropped, jobs,
      [&](const Sequence& seq) { numbering.add(sequence_task(g, seq, options), set); }, &memo, seeing);
}

// Level 4's candidates, with what making them dropped and said; they need nothing of Levels 1-3.
// Move-only: a copy's candidates would point into the original's templates.
struct OutcomeCandidates {
  OutcomeCandidates() = default;
  OutcomeCandidates(OutcomeCandidates&&) = default;
  OutcomeCandidates& operator=(OutcomeCandidates&&) = default;
  OutcomeCandidates(const OutcomeCandidates&) = delete;
  OutcomeCandidates& operator=(const OutcomeCandidates&) = delete;

  std::vector<OutcomeTemplate> templates;  // the candidates point into it
  std::vector<OutcomeTask> tasks;
  std::vector<std::string> warnings;
  DropCounts dropped;
};

OutcomeCandidates make_outcome_candidates(const graph::SceneGraph& g, const episode::WorldState& initial,
                                          const TaskOptions& options,
                                          std::shared_ptr<episode::PlacementTables> shared_tables,
                                          const render::VisibilityOracle* seeing) {
  OutcomeCandidates out;
  out.templates = load_templates(options.level4_templates);
  // Its plans all start from the initial state: whole results repeat. The geometry tables are
  // Levels 1-3's: nearly every interior Level 4 needs, they need too.
  episode::PlacementMemo memo(/*keep_whole_results=*/true, std::move(shared_tables));
  out.tasks = generate_outcomes(g, initial, out.templates, options, out.warnings, out.dropped, &memo, seeing);
  return out;
}

// Level 4: outcome candidates from the templates, then the votes (rules, live voters, recorded).
void add_outcome_tasks(const graph::SceneGraph& g, OutcomeCandidates made, const TaskOptions& options,
                       const std::vector<Vote>& recorded_votes, const std::vector<VoteBatch>& live_voters,
                       TaskNumbering& numbering, GenerationResult& result) {
  result.set.warnings.insert(result.set.warnings.end(), made.warnings.begin(), made.warnings.end());
  result.set.dropped.merge(made.dropped);
  // Candidates first (ids are fixed by their order), then every voter on all of them at once.
  std::vector<std::pair<std::string, Task>> candidates;
  for (OutcomeTask& o : made.tasks) {
    Task t;
    t.level = 4;
    t.scene = g.scene;
    t.type = std::string("outcome:") + to_string(o.tmpl->kind);
    t.template_id = o.tmpl->id;
    t.text = o.text;
    t.goal = {{"outcome", to_json(g, o.goal)}};
    t.identify = std::move(o.identify);
    t.oracle = o.oracle;
    t.oracle.push_back("0");
    // Room beyond the oracle's plan, and for a person who moves each object the goal lists on its
    // own (the oracle carries a stack at once): five keys a move, the end, and two to spare.
    t.step_limit = std::max({options.rules.step_limit, static_cast<int>(t.oracle.size()) + 4, 5 * o.moved + 3});
    candidates.emplace_back(task_id(g.scene, 4, numbering.peek(4) + candidates.size()), std::move(t));
  }
  std::vector<Vote> all_votes;
  for (const auto& [id, t] : candidates) all_votes.push_back({id, "rules", kFeasible});
  if (!live_voters.empty() && !candidates.empty()) {
    std::vector<VoteRequest> requests;
    const std::string scene = describe_scene(g);
    for (const auto& [id, t] : candidates) requests.push_back({id, g.scene, t.text, scene, t.step_limit});
    for (const VoteBatch& voter : live_voters) {
      const std::vector<Vote> cast = voter(requests);
      all_votes.insert(all_votes.end(), cast.begin(), cast.end());
    }
  }
  all_votes.insert(all_votes.end(), recorded_votes.begin(), recorded_votes.end());
  auto votes_by_task = group_votes(all_votes);
  std::size_t vetoed = 0;
  for (auto& [id, t] : candidates) {
    const std::vector<Vote>& votes = votes_by_task[id];
    if (!accepted(votes)) {
      ++vetoed;
      numbering.skip(4);  // ids stay stable whether or not votes veto earlier tasks
      continue;
    }
    result.votes.insert(result.votes.end(), votes.begin(), votes.end());
    numbering.add(std::move(t), result.set);
  }
  if (vetoed > 0) result.set.warnings.push_back("level 4: " + std::to_string(vetoed) + " task(s) vetoed by votes");
}

}  // namespace

GenerationResult generate_tasks(const scene::Scene& scene, const graph::SceneGraph& g, const TaskOptions& options,
                                const std::vector<Vote>& recorded_votes, const std::vector<VoteBatch>& live_voters,
                                int jobs, const TaskSink& sink) {
  if (!options.visibility) return generate_tasks(g, options, recorded_votes, live_voters, jobs, sink);
  const render::SceneGeometry geometry(scene, g);
  const render::VisibilityOracle seeing(g, geometry, *options.visibility);
  return generate_tasks(g, options, recorded_votes, live_voters, jobs, sink, &seeing);
}

GenerationResult generate_tasks(const graph::SceneGraph& g, const TaskOptions& options,
                                const std::vector<Vote>& recorded_votes, const std::vector<VoteBatch>& live_voters,
                                int jobs, const TaskSink& sink, const render::VisibilityOracle* seeing) {
  if (options.visibility && seeing == nullptr) {
    throw Error("task generation: the visibility rules need the scene's meshes (or options without visibility)");
  }
  if (!options.visibility) seeing = nullptr;
  if (seeing != nullptr) seeing->prepare(jobs);
  for (const int level : options.levels) {
    if (level < 1 || level > 4) throw Error("unknown level " + std::to_string(level) + " (levels are 1..4)");
  }
  if (g.navigable.empty()) {
    throw Error("scene " + g.scene + " has no navigable platform: no task can be generated");
  }
  GenerationResult result;
  TaskSet& set = result.set;
  set.scene = g.scene;
  const episode::WorldState initial = episode::initial_state(g);
  set.coverage = to_json(coverage_items(g, initial, options.ambiguity, seeing));
  TaskNumbering numbering(g.scene, sink);
  episode::PlacementMemo memo;  // Levels 1-3 of this scene, on every thread

  // Level 4 is made on one thread of its own alongside Levels 1-3 when there are threads to
  // spare (its work is serial, and would otherwise leave them idle at the end); it is numbered
  // after Level 3 all the same, so the set is the one a single thread makes.
  std::future<OutcomeCandidates> outcomes;
  if (options.levels.count(4) && jobs > 1) {
    outcomes = std::async(std::launch::async, [&g, &initial, &options, tables = memo.tables, seeing] {
      return make_outcome_candidates(g, initial, options, tables, seeing);
    });
  }
  std::vector<AtomicTask> atomic;
  const bool want_atomic = options.levels.count(1) || options.levels.count(2) || options.levels.count(3);
  const bool want_levels_1_2 = options.levels.count(1) || options.levels.count(2);
  if (want_atomic) {
    atomic = enumerate_atomic(g, initial, options, {}, want_levels_1_2 ? &set.dropped : nullptr, jobs, &memo);
  }
  if (want_levels_1_2) add_atomic_tasks(g, initial, atomic, options, numbering, set, seeing);
  if (options.levels.count(3)) add_sequence_tasks(g, initial, atomic, options, numbering, set, jobs, memo, seeing);
  std::vector<AtomicTask>().swap(atomic);  // Level 4 does not need it
  if (options.levels.count(4)) {
    OutcomeCandidates made =
        outcomes.valid() ? outcomes.get() : make_outcome_candidates(g, initial, options, memo.tables, seeing);
    add_outcome_tasks(g, std::move(made), options, recorded_votes, live_voters, numbering, result);
  }
  numbering.flush(set);
  return result;
}

}  // namespace mtg::tasks
