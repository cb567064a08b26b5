#include "core/episode/rules.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>

#include "core/util/error.h"

namespace mtg::episode {
namespace {

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

const graph::Platform& current(const graph::SceneGraph& g, const WorldState& s) {
  return g.platforms.at(s.at_platform);
}

std::string platform_title(const graph::SceneGraph& g, graph::PlatformId platform) {
  const graph::Platform& p = g.platforms[platform];
  return p.name + " (" + graph::navigation_key(p.label) + ")";
}

// What a placement target offers, in the words of the action space: which side of which object,
// the object by its number where it has one (the numbers of the platform's marked view), else by
// what it is and the letter the placing view marks it with (`lettered`, lettered_anchors).
std::string target_description(const graph::SceneGraph& g, const PlaceTarget& t, const RuleOptions& options,
                               const std::vector<graph::ObjectId>& numbering,
                               const std::vector<graph::ObjectId>& lettered) {
  switch (t.kind) {
    case PlaceTarget::Kind::kGridCell:
      return std::string("place it in the ") + graph::direction_name(t.relative_dir) + " part of the platform (grid cell " +
             t.key + ")";
    case PlaceTarget::Kind::kObjectRegion: {
      std::string anchor;
      const auto letter = std::find(lettered.begin(), lettered.end(), t.anchor);
      if (options.object_names) {
        anchor = "the " + listed_name(g.objects[t.anchor]);
        if (letter != lettered.end()) anchor += " marked " + anchor_letter(static_cast<std::size_t>(letter - lettered.begin()));
      } else if (const auto it = std::find(numbering.begin(), numbering.end(), t.anchor); it != numbering.end()) {
        anchor = "object " + std::to_string(it - numbering.begin() + 1);
      } else {
        // Not numbered (scenery): by its letter in the placing view, and what it is.
        const graph::GraphObject& o = g.objects[t.anchor];
        anchor = "the " + (o.noun.empty() ? display_name(o) : o.noun) + " marked " +
                 anchor_letter(static_cast<std::size_t>(letter - lettered.begin()));
      }
      return std::string("place it in free space ") + t.key + ": " + graph::direction_name(t.relative_dir) + " of " +
             anchor;
    }
    case PlaceTarget::Kind::kAnywhere:
      break;
  }
  return "place it anywhere on the platform where it fits";
}

// Where an object stands on the platform the robot is at, as the robot sees it: centimetres
// left/right of and near/far from the platform's centre, or what it rests on.
std::string object_place(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object,
                         const std::vector<graph::ObjectId>& numbering) {
  const ObjectState& o = s.objects[object];
  const auto& siblings = objects_on(s, s.at_platform);
  if (std::find(siblings.begin(), siblings.end(), object) == siblings.end()) {
    for (std::size_t k = 0; k < numbering.size(); ++k) {
      if (!numbering[k].valid()) continue;  // a retired number
      for (const graph::PlatformId p : g.objects[numbering[k]].platforms) {
        if (p == o.parent) return "on object " + std::to_string(k + 1);
      }
    }
    return "on another object";
  }
  const geom::Point2 c_P = platform_frame(g, s, s.at_platform).inverse() * footprint_centre(o);
  const auto side = static_cast<graph::Side>(s.side);
  auto along = [&](int relative_dir) {  // unit vector of a robot-relative side direction, in P
    const Eigen::Vector2i step = graph::direction_step(graph::platform_direction(relative_dir, side));
    return Eigen::Vector2d(step.x(), step.y());
  };
  const double right = c_P.dot(along(6)), far = c_P.dot(along(4));
  auto cm = [](double m) { return std::to_string(static_cast<long>(std::lround(std::abs(m) * 100.0))) + " cm "; };
  return cm(right) + (right < 0 ? "left" : "right") + ", " + cm(far) + (far < 0 ? "near" : "far");
}

// The numbers of `numbering` in use, as words: "3", "1 and 2", "1 to 5", "1, 2 and 4", "1 to 3 and 6".
std::string numbers_in_words(const std::vector<graph::ObjectId>& numbering) {
  std::vector<std::string> runs;
  for (std::size_t k = 0; k < numbering.size();) {
    if (!numbering[k].valid()) {
      ++k;
      continue;
    }
    std::size_t last = k;
    while (last + 1 < numbering.size() && numbering[last + 1].valid()) ++last;
    if (last >= k + 2) {
      runs.push_back(std::to_string(k + 1) + " to " + std::to_string(last + 1));
    } else {
      for (std::size_t i = k; i <= last; ++i) runs.push_back(std::to_string(i + 1));
    }
    k = last + 1;
  }
  std::string out;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == runs.size() ? " and " : ", ") + runs[i];
  }
  return out;
}

std::size_t count_numbered(const std::vector<graph::ObjectId>& numbering) {
  return static_cast<std::size_t>(
      std::count_if(numbering.begin(), numbering.end(), [](graph::ObjectId o) { return o.valid(); }));
}

void end(WorldState& s, StepOutcome& out, EndReason reason) {
  s.phase = Phase::kDone;
  out.done = true;
  out.end_reason = reason;
}

// Whether action_space() offers `key` outside placing, without writing every option's
// description: apply_action() asks on every step, and task generation plays millions of steps.
// RulesTest.TheKeysAStepAcceptsAreTheOnesTheActionSpaceOffers holds the two together.
bool offered_outside_placing(const graph::SceneGraph& g, const WorldState& s, std::string_view key) {
  const bool at_platform = s.phase == Phase::kAtPlatform;
  if (key == "0") return true;
  if (key == "-1") return at_platform;
  if (key == "startplace") return at_platform && s.held.valid();
  // l<n> and o<n>, numbered from 1 without leading zeros (as action_space writes them).
  if (key.size() < 2 || key[1] == '0') return false;
  std::size_t n = 0;
  const auto [end, error] = std::from_chars(key.data() + 1, key.data() + key.size(), n);
  if (error != std::errc{} || end != key.data() + key.size()) return false;
  if (key[0] == 'l') return n <= g.navigable.size();
  if (key[0] == 'o') {
    if (!at_platform || s.held.valid()) return false;
    const std::vector<graph::ObjectId> numbering = numbered_on(g, s, s.at_platform);
    return n <= numbering.size() && numbering[n - 1].valid();
  }
  return false;
}

// Why a key of the vocabulary is not offered in `s`, in the agent's words.
std::string why_unavailable(const graph::SceneGraph& g, const WorldState& s, std::string_view key,
                            const std::vector<PlaceTarget>& targets) {
  const bool at_platform = s.phase == Phase::kAtPlatform || s.phase == Phase::kPlacing;
  const std::string labels = "the platforms are l1 to l" + std::to_string(g.navigable.size());
  if (s.phase == Phase::kPlacing) {
    if (key[0] == 'l' || key[0] == 'o' || key == "-1" || key == "startplace") {
      return "you are placing the object in your hand; choose one of the numbered places, 999 for anywhere it "
             "fits, or 0 to end";
    }
    std::string places;
    for (const PlaceTarget& t : targets) {
      if (t.key != kAnywhereKey) places += (places.empty() ? "" : ", ") + t.key;
    }
    return places.empty() ? "this platform offers no numbered place for the object; 999 puts it anywhere it fits"
                          : "the numbered places here are " + places + " (999: anywhere it fits)";
  }
  if (key[0] == 'l') return labels;
  if (key == "-1") return "you are not at a platform yet";
  if (key == "startplace") {
    if (!at_platform) return "you are not at a platform yet";
    return "your hand is empty";
  }
  if (key[0] == 'o') {
    if (!at_platform) return "you are not at a platform yet; go to one with its l key first";
    if (s.held.valid()) return "your hand is full; place what you hold first (startplace)";
    const std::vector<graph::ObjectId> numbering = numbered_on(g, s, s.at_platform);
    const std::size_t n = count_numbered(numbering);
    if (n == 0) return "there is nothing to pick up on this platform";
    return n == 1 ? "this platform has object " + numbers_in_words(numbering) + " only"
                  : "the objects here are " + numbers_in_words(numbering);
  }
  // A number outside placing.
  return "numbered places are chosen after startplace, with an object in your hand";
}

}  // namespace

const char* to_string(LookalikeAid aid) {
  switch (aid) {
    case LookalikeAid::kBoth: return "both";
    case LookalikeAid::kImage: return "image";
    case LookalikeAid::kWords: return "words";
  }
  return "both";
}

LookalikeAid lookalike_aid_from_string(std::string_view name, std::string_view what) {
  for (const LookalikeAid a : {LookalikeAid::kBoth, LookalikeAid::kImage, LookalikeAid::kWords}) {
    if (name == to_string(a)) return a;
  }
  throw Error(std::string(what) + " is image, words or both, not '" + std::string(name) + "'");
}

bool is_action_key(std::string_view key) {
  if (key == "0" || key == "-1" || key == "startplace" || all_digits(key)) return true;
  return key.size() >= 2 && (key[0] == 'l' || key[0] == 'o') && all_digits(key.substr(1));
}

int next_usable_side(const graph::Platform& p, int from) {
  for (int k = 1; k <= 4; ++k) {
    const int side = (from + k) % 4;
    if (p.sides[static_cast<std::size_t>(side)].usable()) return side;
  }
  return -1;
}

std::vector<ActionOption> action_space(const graph::SceneGraph& g, const WorldState& s,
                                       const RuleOptions& options) {
  std::vector<ActionOption> out;
  if (s.phase == Phase::kDone) return out;
  if (s.phase == Phase::kPlacing) {
    out.push_back({"0", "call_end: finish the task now"});
    const std::vector<graph::ObjectId> numbering = numbered_on(g, s, s.at_platform);
    const std::vector<PlaceTarget> targets =
        place_targets(g, s, s.at_platform, static_cast<graph::Side>(s.side), options.min_region_size);
    const std::vector<graph::ObjectId> lettered = lettered_anchors(targets, numbering);
    for (const PlaceTarget& t : targets) out.push_back({t.key, target_description(g, t, options, numbering, lettered)});
    return out;
  }
  if (s.phase == Phase::kAtPlatform) {
    out.push_back({"-1", "rotate clockwise to the next side of this platform where you fit "
                         "(you stay if there is none)"});
  }
  out.push_back({"0", "call_end: finish the task now"});
  if (s.phase == Phase::kAtPlatform && !s.held.valid()) {
    const auto objects = numbered_on(g, s, s.at_platform);
    for (std::size_t k = 0; k < objects.size(); ++k) {
      if (!objects[k].valid()) continue;  // a retired number
      std::string what = "pick up object " + std::to_string(k + 1);
      if (options.object_names) what += " (" + listed_name(g.objects[objects[k]]) + ")";
      out.push_back({"o" + std::to_string(k + 1), std::move(what)});
    }
  }
  for (std::size_t k = 0; k < g.navigable.size(); ++k) {
    out.push_back({graph::navigation_key(static_cast<int>(k) + 1),
                   "go to platform " + std::to_string(k + 1) + ": " +
                       g.platforms[g.navigable[k]].name});
  }
  if (s.phase == Phase::kAtPlatform && s.held.valid()) {
    out.push_back({"startplace", "start placing the object in your hand on this platform"});
  }
  return out;
}

StepOutcome apply_action(const graph::SceneGraph& g, WorldState& s, std::string_view key,
                         const TaskConstraints& constraints, const RuleOptions& options, PlacementMemo* memo) {
  StepOutcome out;
  if (s.phase == Phase::kDone) {
    out.hint = "the episode has ended";
    return out;
  }
  ++s.steps;
  out.valid = is_action_key(key);
  // While placing, the offered keys are the targets; compute them once for both checks. Ending
  // and "anywhere" are always offered: they need none of the free spaces.
  std::vector<PlaceTarget> targets;
  if (s.phase == Phase::kPlacing && key == kAnywhereKey) {
    targets.push_back(anywhere_target(current(g, s)));
    out.available = true;
  } else if (s.phase == Phase::kPlacing && key == "0") {
    out.available = true;
  } else if (s.phase == Phase::kPlacing) {
    targets = place_targets(g, s, s.at_platform, static_cast<graph::Side>(s.side), options.min_region_size, memo);
    out.available = std::any_of(targets.begin(), targets.end(), [&](const PlaceTarget& t) { return t.key == key; });
  } else {
    out.available = offered_outside_placing(g, s, key);
  }
  if (!out.valid) {
    out.hint = "'" + std::string(key.substr(0, 40)) + "' is not an action key; answer with one key of the action space";
  } else if (!out.available) {
    out.hint = std::string(key) + " is not available here: " + why_unavailable(g, s, key, targets) +
               "; choose one of the offered keys";
  } else if (key == "0") {
    out.applied = true;
    end(s, out, EndReason::kCallEnd);
    return out;
  } else if (key[0] == 'l' && key.size() > 1) {
    const int n = std::stoi(std::string(key.substr(1)));
    s.at_platform = g.navigable[static_cast<std::size_t>(n - 1)];
    s.side = current(g, s).default_side;
    s.phase = Phase::kAtPlatform;
    out.applied = true;
  } else if (key == "-1") {
    const int next = next_usable_side(current(g, s), s.side);
    if (next < 0 || next == s.side) {
      out.hint = "there is no other side of this platform where you fit; you stay where you are";
    } else {
      s.side = next;
      out.applied = true;
    }
  } else if (key[0] == 'o') {
    const int k = std::stoi(std::string(key.substr(1)));
    const graph::ObjectId object = numbered_on(g, s, s.at_platform).at(static_cast<std::size_t>(k - 1));
    const auto& forbidden = constraints.protected_objects;
    if (std::find(forbidden.begin(), forbidden.end(), object) != forbidden.end()) {
      out.hint = "object " + std::to_string(k) + " is a reference object of the task and must stay where it is";
    } else {
      pick(g, s, object);
      out.picked = object;
      out.applied = true;
    }
  } else if (key == "startplace") {
    const double height = stack_height(g, s, s.held);
    const double clearance = current(g, s).clearance;
    if (height > clearance) {
      auto cm = [](double m) { return std::to_string(static_cast<long>(std::lround(m * 100.0))) + " cm"; };
      out.hint = "what you hold is " + cm(height) + " tall with what stands on it, and this platform has " +
                 cm(clearance) + " of free height; choose another platform";
    } else {
      s.phase = Phase::kPlacing;
      out.applied = true;
    }
  } else {  // a placement target
    const auto it = std::find_if(targets.begin(), targets.end(), [&](const PlaceTarget& t) { return t.key == key; });
    const FeasibleCentres feasible = held_feasible_centres(g, s, s.at_platform, memo);
    const auto xy = resolve_target(g, s, s.at_platform, *it, feasible, memo);
    if (!xy) {
      out.hint = "the object does not fit in " + std::string(key == kAnywhereKey ? "any free space of this platform"
                                                                                  : "free space " + std::string(key)) +
                 "; choose another place or another platform";
    } else {
      out.placed = s.held;
      place_held(g, s, s.at_platform, *xy);
      s.phase = Phase::kAtPlatform;
      out.applied = true;
    }
  }
  if (s.steps >= options.step_limit) end(s, out, EndReason::kStepLimit);
  return out;
}

std::string observation_text(const graph::SceneGraph& g, const WorldState& s, const RuleOptions& options) {
  return situation_text(g, s, options) + " You have used " + std::to_string(s.steps) + " of " +
         std::to_string(options.step_limit) + " steps.";
}

const char* direction_convention() {
  return "Directions and parts are named from where you stand when you place the object: front is the part "
         "farthest from you, rear the part nearest you, left and right are your left and right.";
}

std::string situation_text(const graph::SceneGraph& g, const WorldState& s, const RuleOptions& options) {
  std::string text;
  if (!s.at_platform.valid()) {
    text = "You are at the start position and have not gone to any platform yet.";
  } else {
    text = "You are standing at the " + std::string(graph::to_string(static_cast<graph::Side>(s.side))) +
           " side of platform " + platform_title(g, s.at_platform) + ".";
  }
  if (s.held.valid()) {
    text += options.object_names ? " You hold the " + listed_name(g.objects[s.held]) + "."
                                 : " You hold an object (shown in the close-up image).";
  } else {
    text += " Your hand is empty.";
  }
  if (s.at_platform.valid()) {
    const auto objects = numbered_on(g, s, s.at_platform);
    const std::size_t n = count_numbered(objects);
    // Once something has left or arrived here (stable numbering keeps the platform's numbers).
    const bool changed = s.at_platform.index() < s.numbered.size() && !s.numbered[s.at_platform].empty();
    if (n == 0) {
      text += " There is nothing you can pick up on this platform.";
    } else if (!options.object_names) {
      const bool contiguous = n == objects.size();
      text += n == 1 ? " One object here can be picked up: object " + numbers_in_words(objects) +
                           " (numbered in the image)."
              : n == 2 && contiguous ? " Objects 1 and 2 here can be picked up (numbered in the image)."
                                     : " Objects " + numbers_in_words(objects) +
                                           " here can be picked up (numbered in the images).";
      // What the numbers of a changed platform mean: a gap is not an object hidden from view, and
      // an object set down here is numbered anew (two raters and a player read "keeps its number
      // for the whole task" as a promise about the object wherever it goes).
      if (changed) {
        text += " Numbers belong to this platform: an object keeps its number while it stays here, the number of an "
                "object taken away is not used again, and an object set down here gets the next new number.";
      }
    } else {
      text += " On this platform (where each stands from its centre, as you face it):";
      bool first = true;
      for (std::size_t k = 0; k < objects.size(); ++k) {
        if (!objects[k].valid()) continue;
        text += std::string(first ? "" : ",") + " object " + std::to_string(k + 1) + " " +
                listed_name(g.objects[objects[k]]) + " [" +
                object_place(g, s, objects[k], objects) + "]";
        first = false;
      }
      text += ".";
    }
  }
  if (s.phase == Phase::kPlacing) {
    text += objects_on(s, s.at_platform).empty()
                ? " The platform is empty: choose one of its nine parts."
                : " Choose a numbered free space next to an object.";
    text += std::string(" ") + direction_convention();
  }
  return text;
}

}  // namespace mtg::episode
