#include "core/tasks/phrasing.h"

#include <array>

#include "core/episode/placement.h"
#include "core/graph/free_space.h"
#include "core/util/hash.h"
#include "core/util/rng.h"

namespace mtg::tasks {
namespace {

// {item}, {source}, {target}, {anchor}, {anchor2}, {direction} are replaced.
constexpr std::array<const char*, 4> kSurface = {
    "Move the {item} from {source} to {target}.",
    "Take the {item} on {source} and put it on {target}.",
    "Pick up the {item} from {source} and place it on {target}.",
    "Put the {item} that is on {source} onto {target}."};
constexpr std::array<const char*, 4> kSurfacePart = {
    "Move the {item} from {source} to the {direction} part of {target}.",
    "Put the {item} from {source} on the {direction} part of {target}.",
    "Take the {item} on {source} and place it in the {direction} part of {target}.",
    "Place the {item} from {source} onto {target}, in its {direction} part."};
constexpr std::array<const char*, 4> kAround = {
    "Move the {item} from {source} next to the {anchor} on {target}.",
    "Put the {item} from {source} beside the {anchor} on {target}.",
    "Take the {item} on {source} and place it close to the {anchor} on {target}.",
    "Place the {item} from {source} near the {anchor}, on {target}."};
constexpr std::array<const char*, 4> kDirection = {
    "Move the {item} from {source} to the {direction} of the {anchor} on {target}.",
    "Put the {item} from {source} on the {direction} side of the {anchor} on {target}.",
    "Take the {item} on {source} and place it {direction} of the {anchor} on {target}.",
    "Place the {item} from {source} to the {direction} of the {anchor}, on {target}."};
constexpr std::array<const char*, 4> kBetween = {
    "Move the {item} from {source} between the {anchor} and the {anchor2} on {target}.",
    "Put the {item} from {source} in between the {anchor} and the {anchor2} on {target}.",
    "Take the {item} on {source} and place it between the {anchor} and the {anchor2} on {target}.",
    "Place the {item} from {source} between the {anchor} and the {anchor2}, on {target}."};

}  // namespace

void replace_all(std::string& s, const std::string& from, const std::string& to) {
  for (std::size_t pos = 0; (pos = s.find(from, pos)) != std::string::npos; pos += to.size()) {
    s.replace(pos, from.size(), to);
  }
}

std::string plural(const std::string& noun) {
  if (noun.empty()) return noun;
  auto ends = [&](const char* suffix) {
    const std::string s(suffix);
    return noun.size() >= s.size() && noun.compare(noun.size() - s.size(), s.size(), s) == 0;
  };
  if (ends("s") || ends("x") || ends("ch") || ends("sh")) return noun + "es";
  if (ends("y") && noun.size() > 1 && std::string("aeiou").find(noun[noun.size() - 2]) == std::string::npos) {
    return noun.substr(0, noun.size() - 1) + "ies";
  }
  return noun + "s";
}

std::string atomic_text(const graph::SceneGraph& g, const episode::AtomicGoal& goal, std::uint64_t seed) {
  using episode::GoalType;
  const auto* templates = &kSurface;
  switch (goal.type) {
    case GoalType::kSurface: templates = &kSurface; break;
    case GoalType::kSurfacePart: templates = &kSurfacePart; break;
    case GoalType::kAround: templates = &kAround; break;
    case GoalType::kDirection: templates = &kDirection; break;
    case GoalType::kBetween: templates = &kBetween; break;
  }
  const std::uint64_t key = fnv1a64(to_json(g, goal).dump());
  Rng rng(derive_seed(seed, key));
  std::string text = (*templates)[rng.uniform_index(templates->size())];
  auto name = [&](int o) { return episode::display_name(g.objects[static_cast<std::size_t>(o)]); };
  replace_all(text, "{item}", name(goal.item));
  replace_all(text, "{source}", g.platforms[static_cast<std::size_t>(goal.source)].name);
  replace_all(text, "{target}", g.platforms[static_cast<std::size_t>(goal.platform)].name);
  if (goal.anchor >= 0) replace_all(text, "{anchor}", name(goal.anchor));
  if (goal.anchor2 >= 0) replace_all(text, "{anchor2}", name(goal.anchor2));
  if (goal.direction >= 0) replace_all(text, "{direction}", graph::direction_name(goal.direction));
  return text;
}

std::string sequence_text(const std::vector<std::string>& parts) {
  std::string text;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    std::string p = parts[i];
    if (i > 0) {
      if (!p.empty()) p[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(p[0])));
      text += ", then ";
    }
    if (i + 1 < parts.size() && !p.empty() && p.back() == '.') p.pop_back();
    text += p;
  }
  return text;
}

}  // namespace mtg::tasks
