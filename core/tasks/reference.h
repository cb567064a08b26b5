#pragma once
// A referring expression as a value: how a task text names one object among look-alikes ("the
// leftmost book", "the cup next to the plate"). What it means geometrically, and how one is
// chosen, is in referring.h.

#include <nlohmann/json.hpp>
#include <string>

namespace mtg::tasks {

enum class Relation { kAlone, kOn, kUnder, kNextTo, kFromLeft, kFromRight, kNearest, kFarthest, kFromTop, kFromBottom };
/// "alone", "on", ... @throws mtg::Error for an unknown name.
Relation relation_from_string(const std::string& name);
const char* to_string(Relation r);
/// Whether the relation names a second object (on, under, next_to).
bool needs_landmark(Relation r);

/// Look-alikes that stand in two rows, one behind the other (spice jars in a rack): an ordinal may
/// count in the near row or the far row only ("near" and "far", not "front" and "back": front is
/// the farthest part at placement, the paper's convention).
enum class Row { kNone, kFront, kBack };

struct Reference {
  Relation relation = Relation::kAlone;
  std::string noun;
  std::string landmark;  // on, under, next_to: the other object's noun
  int rank = 0;          // from_left, from_right, from_top, from_bottom: 1 = the first; nearest, farthest: 1
  Row row = Row::kNone;  // from_left, from_right: counted in that row only
  int stack = 0;         // from_top, from_bottom: in the stack-th stack from the left (0: the one stack)
  bool stack_from_right = false;  // the stack-th from the right instead

  /// "the book", "the book on the box", "the leftmost book", "the second book from the right",
  /// "the leftmost spice jar in the far row", "the book at the top of the rightmost stack"...
  std::string phrase() const;
  nlohmann::json to_json() const;
  /// @throws mtg::Error naming the field.
  static Reference from_json(const nlohmann::json& j);
};

}  // namespace mtg::tasks
