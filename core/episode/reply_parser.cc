#include "core/episode/reply_parser.h"

#include <algorithm>
#include <cctype>
#include <set>

#include "core/episode/rules.h"

namespace mtg::episode {
namespace {

constexpr std::size_t kMaxReply = 64 * 1024;

bool is_token_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_';
}

// Tokens of the reply in order: runs of letters, digits, '-' and '_'.
std::vector<std::string> tokens(std::string_view text) {
  std::vector<std::string> out;
  std::string cur;
  for (const char c : text) {
    if (is_token_char(c)) {
      cur += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else if (!cur.empty()) {
      out.push_back(cur);
      cur.clear();
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n`'\"*.");
  if (b == std::string_view::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n`'\"*.");
  return std::string(s.substr(b, e - b + 1));
}

}  // namespace

namespace {

// The key a reply gives among `keys`, by the steps below in order, or "" (with `why`).
// `bare_numbers`: whether a number standing alone among other words may count (not when looking
// for keys outside the offer: "I see 3 books" names no key).
std::string find_key(std::string_view reply, const std::set<std::string>& keys, bool bare_numbers, std::string& why) {
  auto usable = [&](const std::string& t) {
    return keys.count(t) != 0 && (bare_numbers || t.empty() || !std::isdigit(static_cast<unsigned char>(t[0])));
  };
  // 1. The whole reply is a key (after stripping quotes, backticks, bold, a final period).
  const std::string whole = trim(reply);
  if (keys.count(whole)) return whole;
  // 2. An explicit "action: <key>" / "answer: <key>" marker; the last one wins.
  std::string lower(reply);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  std::string marked;
  for (const char* marker : {"action:", "answer:", "key:", "final answer:"}) {
    for (std::size_t pos = lower.find(marker); pos != std::string::npos; pos = lower.find(marker, pos + 1)) {
      const auto t = tokens(std::string_view(reply).substr(pos + std::string(marker).size(), 40));
      if (!t.empty() && keys.count(t.front())) marked = t.front();
    }
  }
  if (!marked.empty()) return marked;
  // 3. The first line, then a code fence, holding exactly one key.
  auto in = [&](std::string_view text) {
    std::set<std::string> found;
    for (const auto& t : tokens(text)) {
      if (usable(t)) found.insert(t);
    }
    return found;
  };
  if (const auto found = in(reply.substr(0, reply.find('\n'))); found.size() == 1) return *found.begin();
  if (const auto fence = reply.find("```"); fence != std::string_view::npos) {
    const auto end = reply.find("```", fence + 3);
    const std::string_view body =
        reply.substr(fence + 3, end == std::string_view::npos ? std::string_view::npos : end - fence - 3);
    if (const auto found = in(body); found.size() == 1) return *found.begin();
  }
  // 4. Exactly one distinct key anywhere.
  const auto found = in(reply);
  if (found.size() == 1) return *found.begin();
  why = found.empty() ? "no offered action key in the reply" : "the reply names several action keys";
  return "";
}

// The keys of the vocabulary a reply's words could be: every token that is one.
std::set<std::string> vocabulary_in(std::string_view reply) {
  std::set<std::string> out;
  for (const auto& t : tokens(reply)) {
    if (is_action_key(t)) out.insert(t);
  }
  const std::string whole = trim(reply);
  if (is_action_key(whole)) out.insert(whole);
  return out;
}

}  // namespace

ParsedReply parse_reply(std::string_view reply, const std::vector<std::string>& offered) {
  ParsedReply out;
  if (reply.size() > kMaxReply) reply = reply.substr(0, kMaxReply);
  const std::set<std::string> keys(offered.begin(), offered.end());
  if (reply.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    out.why = "empty reply";
    return out;
  }
  std::string why;
  if (std::string key = find_key(reply, keys, true, why); !key.empty()) return {key, true, true, ""};
  // No offered key: a real key that is not offered now is an action the rules refuse, not a
  // reply that cannot be read.
  std::string ignored;
  const std::set<std::string> vocabulary = vocabulary_in(reply);
  if (std::string key = find_key(reply, vocabulary, false, ignored); !key.empty()) return {key, true, false, ""};
  out.why = why;
  return out;
}

}  // namespace mtg::episode
