#include "core/episode/reply_parser.h"

#include <algorithm>
#include <cctype>
#include <set>

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

// The distinct offered keys among the tokens of `text`.
std::set<std::string> offered_in(std::string_view text, const std::set<std::string>& keys) {
  std::set<std::string> found;
  for (const auto& t : tokens(text)) {
    if (keys.count(t)) found.insert(t);
  }
  return found;
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
  // 1. The whole reply is a key (after stripping quotes, backticks, bold, a final period).
  const std::string whole = trim(reply);
  if (keys.count(whole)) return {whole, true, ""};
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
  if (!marked.empty()) return {marked, true, ""};
  // 3. The first line, then a code fence, holding exactly one offered key.
  if (const auto found = offered_in(reply.substr(0, reply.find('\n')), keys); found.size() == 1) {
    return {*found.begin(), true, ""};
  }
  if (const auto fence = reply.find("```"); fence != std::string_view::npos) {
    const auto end = reply.find("```", fence + 3);
    const std::string_view body =
        reply.substr(fence + 3, end == std::string_view::npos ? std::string_view::npos : end - fence - 3);
    if (const auto found = offered_in(body, keys); found.size() == 1) return {*found.begin(), true, ""};
  }
  // 4. Exactly one distinct offered key anywhere (ignoring bare numbers that are not keys).
  const auto found = offered_in(reply, keys);
  if (found.size() == 1) return {*found.begin(), true, ""};
  out.why = found.empty() ? "no offered action key in the reply" : "the reply names several action keys";
  return out;
}

}  // namespace mtg::episode
