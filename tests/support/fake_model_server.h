#pragma once
// A real HTTP server on 127.0.0.1 that speaks the three providers' wire formats (OpenAI chat
// completions, Anthropic Messages, Gemini generateContent), for the adapter tests, the end-to-end
// runs and scripts/bench. It can be scripted, request by request, to answer, stall, return any
// status with any headers (429 with Retry-After, 500, 529, 401...), return malformed JSON or cut
// the connection mid-body; it can enforce a requests-per-window limit itself (429 when exceeded),
// and it records every request it saw (path, headers, body, arrival time).

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace mtg::testing {

/// A request in provider-neutral form, as the model sees it.
struct SeenChat {
  std::string provider;  // "openai", "anthropic", "gemini"
  std::string system;
  std::vector<std::pair<std::string, std::string>> turns;  // ("user" | "assistant", text)
  int images = 0;                                           // in the whole request
  int last_turn_images = 0;
};

struct SeenRequest {
  std::string path;
  std::map<std::string, std::string> headers;  // names lower-cased
  std::string body;
  SeenChat chat;
  double at_ms = 0.0;   // since the server started
  double handle_ms = 0.0;  // time spent in the handler (parsing and answering; no artificial latency)
  int status = 0;       // what it answered
};

struct Behaviour {
  enum class Kind { kAnswer, kStatus, kStall, kMalformed, kCut };
  Kind kind = Kind::kAnswer;
  int status = 200;
  std::string body;                              // kStatus: the error body
  std::map<std::string, std::string> headers;    // kStatus: e.g. retry-after
  int stall_ms = 0;                              // kStall: then it answers
  std::string text;                              // kAnswer: "" = ask the model function
};

class FakeModelServer {
 public:
  /// The model: the reply text for a request (default: "l1").
  using Model = std::function<std::string(const SeenChat&)>;

  /// Listens on `address` (another host of a multi-host test reaches it on the bridge's address).
  explicit FakeModelServer(const std::string& address = "127.0.0.1");
  ~FakeModelServer();
  FakeModelServer(const FakeModelServer&) = delete;
  FakeModelServer& operator=(const FakeModelServer&) = delete;

  int port() const { return port_; }
  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  /// The next requests get these behaviours, in order; after them, kAnswer.
  void script(std::vector<Behaviour> behaviours);
  void set_model(Model model);
  /// Answer 429 (with retry-after) to requests beyond `rpm` within `window`. 0 = no limit.
  void enforce_limit(int rpm, std::chrono::milliseconds window);
  /// Extra time each answer takes (a model's thinking time).
  void set_latency(std::chrono::milliseconds latency);
  std::vector<SeenRequest> requests() const;
  int answered_429() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
};

/// A scripted model that plays each task's oracle plan: it finds the task by the "Task: <text>"
/// line of the conversation's first user turn and answers the plan's k-th key at step k, in
/// rotating messy formats (bare, "Action: l3", fenced, quoted, with explanations).
FakeModelServer::Model oracle_model(const std::map<std::string, std::vector<std::string>>& plans_by_text);

}  // namespace mtg::testing
