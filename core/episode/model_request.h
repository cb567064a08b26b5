#pragma once
// What a model agent sent for one step, kept so a person can read the request verbatim later
// (agent_action_t.request, the viewer's "What the model received"). A request repeats the whole
// conversation, so storing each in full would grow with the square of an episode's length: the
// record names earlier turns by their step instead. The system text and the generation
// parameters are written in the attempt's first request, a user turn's text in its own step's
// request, and an assistant turn is the step's recorded reply (agent_action_t.raw_reply).
// Images are named by the observation image they came from plus the SHA-256 of the bytes sent
// (different from the recorded image when the adapter shrank it). docs/vlm.md.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mtg::episode {

/// One image as sent: which image of which step's observation, and the bytes' identity.
struct SentImage {
  int step = 0;
  int index = 0;  // in that observation's images
  std::string mime;
  int width = 0, height = 0;  // as sent
  std::string sha256;         // of the bytes sent
};

struct SentMessage {
  enum class Role { kSystem, kUser, kAssistant };
  Role role = Role::kUser;
  int step = -1;  // user and assistant turns: the step they belong to
  std::string text;
  std::vector<SentImage> images;
};

struct SentRequest {
  int step = 0;
  std::vector<SentMessage> messages;  // in the order sent, the system message first
  nlohmann::json params = nlohmann::json::object();  // generation parameters and windowing
};

/// The compact JSON of `request` (see the file comment). `first` says whether it is its
/// attempt's first request, which carries the system text and the parameters.
std::string request_record(const SentRequest& request, bool first);

/// Every step's request in full from one attempt's records and replies (by step): {"step",
/// "params", "messages": [{"role", "step", "text", "images": [{"step", "index", "mime", "width",
/// "height", "sha256"}]}]}. A piece whose record is missing (a damaged recording) has text null
/// and "missing": true; a record that does not parse gives {"error": ...} for that step.
std::map<int, nlohmann::json> resolve_requests(const std::map<int, std::string>& records,
                                               const std::map<int, std::string>& replies);

}  // namespace mtg::episode
