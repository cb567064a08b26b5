#pragma once
// The one table of Level 4 outcome kinds: each kind's name, the placeholders its templates may
// and must use, and what a scene must offer for it to make any task (said in a warning where a
// kind makes none). Template files are checked against it when they load (outcome.h).

#include <set>
#include <string>
#include <vector>

#include "core/tasks/outcome.h"

namespace mtg::tasks {

struct KindSpec {
  OutcomeKind kind;
  const char* name;
  std::set<std::string> allowed;
  std::vector<std::set<std::string>> required;  // each: at least one of these
  const char* needs;                            // what the scene must offer, in words
};

/// Every kind, in the order of OutcomeKind.
const std::vector<KindSpec>& outcome_kinds();
/// The kind with that name, or nullptr.
const KindSpec* spec_named(const std::string& name);
/// The placeholder names in a template text ("{source}" -> "source").
std::set<std::string> placeholders_of(const std::string& text);

}  // namespace mtg::tasks
