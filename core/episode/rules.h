#pragma once
// The paper's action state machine (DESIGN.md §3 "Episode", official-impl-spec §6.1), as free
// functions of a const scene graph and a mutable world state.
//
//   start            0 call_end, l1..lN go to platform N
//   at a platform    -1 rotate clockwise to the next side the robot can use, 0, l1..lN,
//                    o1..oM pick object M (hand empty), startplace (holding)
//   placing          0, 1..K the numbered targets (placement.h), 999 anywhere it fits
// An invalid or unavailable key consumes the step and returns a hint; so does a target too
// small for the object (the robot keeps holding it and stays in placing) and `startplace` under
// a clearance lower than the held object together with what rests on it. The episode ends on
// call_end or when the step limit is used up.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/episode/outcomes.h"
#include "core/episode/placement.h"
#include "core/episode/world_state.h"

namespace mtg::episode {

/// How the agent tells a task's look-alikes apart (issue 53). The paper's Level 2 agent
/// "disambiguates using additional task-provided descriptions or images": kBoth gives the words and
/// a close-up of each look-alike (the default); kWords the words alone, so a run measures whether a
/// model understands "the second cup from the left"; kImage the close-ups alone, the text calling
/// each look-alike "the cup in close-up 1" (core/tasks/lookalike_aid.h).
enum class LookalikeAid : std::int8_t { kBoth = 0, kImage = 1, kWords = 2 };
/// "both", "image", "words".
const char* to_string(LookalikeAid aid);
/// The aid called `name`. @throws mtg::Error "<what> is image, words or both, not '<name>'".
LookalikeAid lookalike_aid_from_string(std::string_view name, std::string_view what);

struct RuleOptions {
  int step_limit = 15;
  double min_region_size = 0.03;
  /// Name objects in the action space and the situation text ("pick up object 3 (cup 01)") and
  /// say where each stands. Off, keys are the paper's ("pick up object 3") and an object is known
  /// by its number in the image only. On is for agents that get no images (docs/episode.md,
  /// "What the agent is told").
  bool object_names = false;
  /// Presentation only: what the observations say and show of look-alikes, never what is judged.
  LookalikeAid lookalike_aid = LookalikeAid::kBoth;
  /// How items are numbered over the episode: the state an episode starts from takes it
  /// (initial_state), and pick and place keep it.
  Numbering numbering = Numbering::kStable;
};

struct ActionOption {
  std::string key;
  std::string description;
};

/// What the task forbids: its anchors must stay where they are (the release refuses to pick them).
struct TaskConstraints {
  std::vector<graph::ObjectId> protected_objects;
};

struct StepOutcome {
  bool valid = false;       // the key is in the action vocabulary
  bool available = false;   // ... and was offered in this state
  bool applied = false;     // the world changed as asked
  std::string hint;         // feedback for the next observation ("" if none)
  graph::ObjectId picked;   // object picked by this step
  graph::ObjectId placed;   // object placed by this step
  bool done = false;        // the episode ended with this step
  EndReason end_reason = EndReason::kNone;
};

/// Keys the agent may answer with now, with descriptions (the observation's action space).
std::vector<ActionOption> action_space(const graph::SceneGraph& g, const WorldState& s,
                                       const RuleOptions& options);

/// Applies one answer. Never throws for bad keys; counts the step. `memo`, when given, keeps the
/// placement geometry for the next calls (placement.h).
StepOutcome apply_action(const graph::SceneGraph& g, WorldState& s, std::string_view key,
                         const TaskConstraints& constraints, const RuleOptions& options,
                         PlacementMemo* memo = nullptr);

/// Where the robot stands and what it holds and sees, in plain English.
std::string situation_text(const graph::SceneGraph& g, const WorldState& s, const RuleOptions& options);

/// An observation's text: the situation and the steps used.
std::string observation_text(const graph::SceneGraph& g, const WorldState& s, const RuleOptions& options);

/// The direction convention as the agent is told it (system prompt, placing text): one sentence,
/// the same rule the judge applies (goals.h) and the placement targets number (placement.h).
const char* direction_convention();

/// True when `key` belongs to the vocabulary at all (l<N>, o<N>, digits, -1, startplace).
bool is_action_key(std::string_view key);

/// The next usable side clockwise after `from` (rear, left, front, right), or -1.
int next_usable_side(const graph::Platform& p, int from);

}  // namespace mtg::episode
