#pragma once
// Reading an action key out of a model's free-text reply: code fences, quotes, "Action: l12",
// trailing explanations. Offered keys are looked for first; the parser never guesses between two.
// A reply that names no offered key but one real key of the vocabulary (o<N>, l<N>, -1,
// startplace, or a number on its own or after "Action:") gives that key, `offered` false: the
// step rules then refuse it as unavailable, with the reason, and it counts as an invalid action,
// not as a reply that could not be read (docs/episode.md, "Reading a reply").

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mtg::episode {

struct ParsedReply {
  std::string key;   // "" when none could be read
  bool ok = false;   // a key was read (offered now or not)
  bool offered = false;  // ... and it is one of the keys offered now
  std::string why;   // for format errors
};

/// `offered` are the keys of the current action space.
ParsedReply parse_reply(std::string_view reply, const std::vector<std::string>& offered);

}  // namespace mtg::episode
