#include "core/tasks/phrasing.h"

#include <array>

#include "core/graph/free_space.h"
#include "core/util/hash.h"
#include "core/util/rng.h"

namespace mtg::tasks {
namespace {

// {item}, {source}, {target}, {anchor}, {anchor2}, {direction} are replaced; objects come with
// their article ("the book", "the leftmost book"). Sources always read "from <platform>", so an
// "on" inside a reference ("the book on the box") is never mistaken for a destination.
constexpr std::array<const char*, 4> kSurface = {
    "Move {item} from {source} to {target}.",
    "Take {item} from {source} and put it on {target}.",
    "Pick up {item} from {source} and place it on {target}.",
    "Bring {item} from {source} to {target}."};
constexpr std::array<const char*, 4> kSurfacePart = {
    "Move {item} from {source} to the {direction} part of {target}.",
    "Put {item} from {source} on the {direction} part of {target}.",
    "Take {item} from {source} and place it in the {direction} part of {target}.",
    "Place {item} from {source} onto {target}, in its {direction} part."};
constexpr std::array<const char*, 4> kAround = {
    "Move {item} from {source} next to {anchor} on {target}.",
    "Put {item} from {source} beside {anchor} on {target}.",
    "Take {item} from {source} and place it close to {anchor} on {target}.",
    "Place {item} from {source} near {anchor}, on {target}."};
constexpr std::array<const char*, 4> kDirection = {
    "Move {item} from {source} to the {direction} of {anchor} on {target}.",
    "Put {item} from {source} on the {direction} side of {anchor} on {target}.",
    "Take {item} from {source} and place it to the {direction} of {anchor} on {target}.",
    "Carry {item} from {source} to the {direction} of {anchor}, on {target}."};
constexpr std::array<const char*, 4> kBetween = {
    "Move {item} from {source} between {anchor} and {anchor2} on {target}.",
    "Put {item} from {source} in between {anchor} and {anchor2} on {target}.",
    "Take {item} from {source} and place it between {anchor} and {anchor2} on {target}.",
    "Place {item} from {source} between {anchor} and {anchor2}, on {target}."};

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

std::string atomic_text(const graph::SceneGraph& g, const episode::AtomicGoal& goal, const Wording& words,
                        std::uint64_t seed) {
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
  replace_all(text, "{item}", words.item.phrase());
  replace_all(text, "{source}", g.platforms[goal.source].name);
  replace_all(text, "{target}", g.platforms[goal.platform].name);
  if (goal.anchor.valid()) replace_all(text, "{anchor}", words.anchor.phrase());
  if (goal.anchor2.valid()) replace_all(text, "{anchor2}", words.anchor2.phrase());
  if (goal.direction >= 0) replace_all(text, "{direction}", graph::direction_name(goal.direction));
  return text;
}

std::string lookalike_hint(const std::vector<Identification>& lookalikes, bool with_images) {
  if (lookalikes.empty()) return "";
  std::string text = "Some objects of this task have look-alikes; the task names them as ";
  for (std::size_t i = 0; i < lookalikes.size(); ++i) {
    if (i > 0) text += i + 1 == lookalikes.size() ? " and " : ", ";
    text += lookalikes[i].phrase + " (on " + lookalikes[i].platform + ")";
  }
  text += ". Left, right, nearest, farthest and the near and far rows are as seen from the side where you arrive "
          "at that platform.";
  if (with_images) {
    text += lookalikes.size() == 1 ? " A close-up image shows it, every other object faded."
                                   : " Close-up images show them in that order, every other object faded.";
  }
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
