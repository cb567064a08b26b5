#pragma once
// Reading an action key out of a model's free-text reply: code fences, quotes, "Action: l12",
// trailing explanations. Only keys offered in the current action space count; the parser never
// guesses between two offered keys.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mtg::episode {

struct ParsedReply {
  std::string key;   // "" when none could be read
  bool ok = false;
  std::string why;   // for format errors
};

/// `offered` are the keys of the current action space.
ParsedReply parse_reply(std::string_view reply, const std::vector<std::string>& offered);

}  // namespace mtg::episode
