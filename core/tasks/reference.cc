#include "core/tasks/reference.h"

#include "core/util/error.h"

namespace mtg::tasks {
namespace {

constexpr int kMaxRank = 5;  // "the fifth book from the left" at most

const char* ordinal(int rank) {
  static const char* kWords[] = {"", "first", "second", "third", "fourth", "fifth"};
  return rank >= 1 && rank <= kMaxRank ? kWords[rank] : "";
}

// "the stack", "the leftmost stack", "the second stack from the right".
std::string stack_words(int stack, bool from_right) {
  if (stack <= 0) return "the stack";
  if (stack == 1) return from_right ? "the rightmost stack" : "the leftmost stack";
  return std::string("the ") + ordinal(stack) + (from_right ? " stack from the right" : " stack from the left");
}

}  // namespace

bool needs_landmark(Relation r) { return r == Relation::kOn || r == Relation::kUnder || r == Relation::kNextTo; }

const char* to_string(Relation r) {
  switch (r) {
    case Relation::kAlone: return "alone";
    case Relation::kOn: return "on";
    case Relation::kUnder: return "under";
    case Relation::kNextTo: return "next_to";
    case Relation::kFromLeft: return "from_left";
    case Relation::kFromRight: return "from_right";
    case Relation::kNearest: return "nearest";
    case Relation::kFarthest: return "farthest";
    case Relation::kFromTop: return "from_top";
    case Relation::kFromBottom: return "from_bottom";
  }
  return "alone";
}

Relation relation_from_string(const std::string& name) {
  for (const Relation r : {Relation::kAlone, Relation::kOn, Relation::kUnder, Relation::kNextTo, Relation::kFromLeft,
                           Relation::kFromRight, Relation::kNearest, Relation::kFarthest, Relation::kFromTop,
                           Relation::kFromBottom}) {
    if (name == to_string(r)) return r;
  }
  throw Error("reference: unknown relation '" + name + "'");
}

std::string Reference::phrase() const {
  if (row != Row::kNone && (relation == Relation::kFromLeft || relation == Relation::kFromRight)) {
    Reference in_row = *this;
    in_row.row = Row::kNone;
    return in_row.phrase() + (row == Row::kFront ? " in the near row" : " in the far row");
  }
  switch (relation) {
    case Relation::kAlone: return "the " + noun;
    case Relation::kOn: return "the " + noun + " on the " + landmark;
    case Relation::kUnder: return "the " + noun + " under the " + landmark;
    case Relation::kNextTo: return "the " + noun + " next to the " + landmark;
    case Relation::kFromLeft:
      return rank <= 1 ? "the leftmost " + noun : std::string("the ") + ordinal(rank) + " " + noun + " from the left";
    case Relation::kFromRight:
      return rank <= 1 ? "the rightmost " + noun : std::string("the ") + ordinal(rank) + " " + noun + " from the right";
    case Relation::kNearest: return "the nearest " + noun;
    case Relation::kFarthest: return "the farthest " + noun;
    case Relation::kFromTop:
      return rank <= 1 ? "the " + noun + " at the top of " + stack_words(stack, stack_from_right)
                       : std::string("the ") + ordinal(rank) + " " + noun + " from the top of " +
                             stack_words(stack, stack_from_right);
    case Relation::kFromBottom:
      return rank <= 1 ? "the " + noun + " at the bottom of " + stack_words(stack, stack_from_right)
                       : std::string("the ") + ordinal(rank) + " " + noun + " from the bottom of " +
                             stack_words(stack, stack_from_right);
  }
  return "the " + noun;
}

nlohmann::json Reference::to_json() const {
  nlohmann::json j = {{"relation", tasks::to_string(relation)}, {"noun", noun}};
  if (!landmark.empty()) j["landmark"] = landmark;
  if (rank > 0) j["rank"] = rank;
  if (row != Row::kNone) j["row"] = row == Row::kFront ? "near" : "far";
  if (stack > 0) j["stack"] = stack;
  if (stack_from_right) j["stack_from"] = "right";
  return j;
}

Reference Reference::from_json(const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("relation") || !j.contains("noun")) {
    throw Error("reference: expected an object with 'relation' and 'noun'");
  }
  Reference r;
  r.relation = relation_from_string(j["relation"].get<std::string>());
  r.noun = j["noun"].get<std::string>();
  r.landmark = j.value("landmark", "");
  r.rank = j.value("rank", 0);
  if (needs_landmark(r.relation) && r.landmark.empty()) throw Error("reference: relation needs 'landmark'");
  const bool ordinal_relation = !needs_landmark(r.relation) && r.relation != Relation::kAlone;
  if (ordinal_relation && (r.rank < 1 || r.rank > kMaxRank)) {
    throw Error("reference: 'rank' must be 1.." + std::to_string(kMaxRank));
  }
  r.stack = j.value("stack", 0);
  if (r.stack != 0 && (r.relation != Relation::kFromTop && r.relation != Relation::kFromBottom)) {
    throw Error("reference: only from_top and from_bottom count in a stack");
  }
  if (r.stack < 0 || r.stack > kMaxRank) throw Error("reference: 'stack' must be 0.." + std::to_string(kMaxRank));
  const std::string stack_from = j.value("stack_from", "left");
  if (stack_from != "left" && stack_from != "right") {
    throw Error("reference: 'stack_from' must be left or right, not '" + stack_from + "'");
  }
  r.stack_from_right = stack_from == "right";
  if (r.stack_from_right && r.stack == 0) throw Error("reference: 'stack_from' needs 'stack'");
  const std::string row = j.value("row", "");
  if (!row.empty()) {
    if (row != "near" && row != "far") throw Error("reference: 'row' must be near or far, not '" + row + "'");
    if (r.relation != Relation::kFromLeft && r.relation != Relation::kFromRight) {
      throw Error("reference: only from_left and from_right count in a row");
    }
    r.row = row == "near" ? Row::kFront : Row::kBack;
  }
  return r;
}

}  // namespace mtg::tasks
