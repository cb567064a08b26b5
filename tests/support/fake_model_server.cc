#include "tests/support/fake_model_server.h"

#include <sys/socket.h>

#include <httplib.h>

#include <algorithm>
#include <deque>

namespace mtg::testing {
namespace {

using Clock = std::chrono::steady_clock;

std::string text_of(const nlohmann::json& content, int& images) {
  if (content.is_string()) return content.get<std::string>();
  std::string text;
  if (!content.is_array()) return text;
  for (const auto& part : content) {
    if (!part.is_object()) continue;
    if (part.contains("text")) text += part["text"].get<std::string>();
    if (part.value("type", "") == "image_url" || part.value("type", "") == "image" || part.contains("inline_data")) {
      ++images;
    }
  }
  return text;
}

SeenChat parse_chat(const std::string& path, const nlohmann::json& body) {
  SeenChat c;
  auto add_turn = [&](const std::string& role, const nlohmann::json& content) {
    int images = 0;
    const std::string text = text_of(content, images);
    c.images += images;
    c.last_turn_images = images;
    c.turns.emplace_back(role, text);
  };
  if (path.find("/chat/completions") != std::string::npos) {
    c.provider = "openai";
    for (const auto& m : body.at("messages")) {
      const std::string role = m.at("role");
      if (role == "system") {
        c.system += m.at("content").get<std::string>();
      } else {
        add_turn(role, m.at("content"));
      }
    }
  } else if (path.find("/v1/messages") != std::string::npos) {
    c.provider = "anthropic";
    c.system = body.value("system", "");
    for (const auto& m : body.at("messages")) add_turn(m.at("role"), m.at("content"));
  } else {
    c.provider = "gemini";
    if (body.contains("systemInstruction")) c.system = body["systemInstruction"]["parts"][0].value("text", "");
    for (const auto& m : body.at("contents")) add_turn(m.at("role") == "model" ? "assistant" : "user", m.at("parts"));
  }
  return c;
}

nlohmann::json answer_body(const std::string& provider, const std::string& text, int in_tokens, int out_tokens) {
  if (provider == "anthropic") {
    return {{"id", "msg_fake"}, {"type", "message"}, {"role", "assistant"},
            {"content", nlohmann::json::array({{{"type", "text"}, {"text", text}}})},
            {"stop_reason", "end_turn"}, {"usage", {{"input_tokens", in_tokens}, {"output_tokens", out_tokens}}}};
  }
  if (provider == "gemini") {
    return {{"candidates", nlohmann::json::array({{{"content", {{"role", "model"}, {"parts", nlohmann::json::array({{{"text", text}}})}}},
                                                  {"finishReason", "STOP"}}})},
            {"usageMetadata", {{"promptTokenCount", in_tokens}, {"candidatesTokenCount", out_tokens}}}};
  }
  return {{"id", "chatcmpl-fake"}, {"object", "chat.completion"},
          {"choices", nlohmann::json::array({{{"index", 0}, {"message", {{"role", "assistant"}, {"content", text}}},
                                              {"finish_reason", "stop"}}})},
          {"usage", {{"prompt_tokens", in_tokens}, {"completion_tokens", out_tokens}}}};
}

}  // namespace

struct FakeModelServer::Impl {
  httplib::Server server;
  std::thread thread;
  mutable std::mutex mutex;
  std::deque<Behaviour> script;
  Model model = [](const SeenChat&) { return std::string("l1"); };
  std::vector<SeenRequest> seen;
  Clock::time_point started = Clock::now();
  int rpm = 0;
  std::chrono::milliseconds window{60000};
  std::deque<Clock::time_point> admitted;
  std::chrono::milliseconds latency{0};
  int rejected = 0;

  void handle(const httplib::Request& req, httplib::Response& res) {
    const auto entered = Clock::now();
    SeenRequest s;
    s.path = req.path;
    s.body = req.body;
    for (const auto& [k, v] : req.headers) {
      std::string name = k;
      std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return std::tolower(ch); });
      s.headers[name] = v;
    }
    Behaviour b;
    bool limited = false;
    {
      std::lock_guard lock(mutex);
      const auto now = Clock::now();
      s.at_ms = std::chrono::duration<double, std::milli>(now - started).count();
      if (!script.empty()) {
        b = script.front();
        script.pop_front();
      }
      if (rpm > 0) {
        while (!admitted.empty() && admitted.front() + window <= now) admitted.pop_front();
        if (static_cast<int>(admitted.size()) >= rpm) {
          limited = true;
          ++rejected;
        } else {
          admitted.push_back(now);
        }
      }
    }
    nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
    if (body.is_discarded()) {
      res.status = 400;
      res.set_content(R"({"error":{"message":"request body is not JSON","type":"invalid_request_error"}})",
                      "application/json");
      record(std::move(s), res.status);
      return;
    }
    try {
      s.chat = parse_chat(req.path, body);
    } catch (const std::exception& e) {
      res.status = 400;
      res.set_content(nlohmann::json({{"error", {{"message", std::string("bad request shape: ") + e.what()}}}}).dump(),
                      "application/json");
      record(std::move(s), res.status);
      return;
    }
    if (limited) {
      res.status = 429;
      res.set_header("retry-after", "1");
      res.set_content(R"({"error":{"message":"Rate limit reached","type":"rate_limit_error","code":"rate_limit_exceeded"}})",
                      "application/json");
      record(std::move(s), res.status);
      return;
    }
    const auto slept = latency;
    if (latency.count() > 0) std::this_thread::sleep_for(latency);
    switch (b.kind) {
      case Behaviour::Kind::kStall:
        std::this_thread::sleep_for(std::chrono::milliseconds(b.stall_ms));
        [[fallthrough]];
      case Behaviour::Kind::kAnswer: {
        const std::string text = b.text.empty() ? model(s.chat) : b.text;
        res.status = 200;
        res.set_content(answer_body(s.chat.provider, text, static_cast<int>(req.body.size() / 4),
                                    static_cast<int>(text.size() / 4 + 1))
                            .dump(),
                        "application/json");
        break;
      }
      case Behaviour::Kind::kStatus:
        res.status = b.status;
        for (const auto& [k, v] : b.headers) res.set_header(k.c_str(), v);
        res.set_content(b.body, "application/json");
        break;
      case Behaviour::Kind::kMalformed:
        res.status = 200;
        res.set_content("{\"choices\": [ {\"message\": ", "application/json");
        break;
      case Behaviour::Kind::kCut:
        res.status = 200;
        // Promise 4096 bytes, send a few, then give up: the client sees the connection close.
        res.set_content_provider(4096, "application/json", [](std::size_t, std::size_t, httplib::DataSink& sink) {
          sink.write("{\"choices\": [", 13);
          return false;
        });
        break;
    }
    s.handle_ms = std::chrono::duration<double, std::milli>(Clock::now() - entered - slept).count();
    record(std::move(s), res.status);
  }

  void record(SeenRequest s, int status) {
    s.status = status;
    std::lock_guard lock(mutex);
    seen.push_back(std::move(s));
  }
};

FakeModelServer::FakeModelServer(const std::string& address) : impl_(std::make_unique<Impl>()) {
  auto handler = [this](const httplib::Request& req, httplib::Response& res) { impl_->handle(req, res); };
  impl_->server.Post(R"(/.*)", handler);
  // Enough threads for 8+ parallel episodes plus stalled requests (the default follows the cores).
  impl_->server.new_task_queue = [] { return new httplib::ThreadPool(24); };
  // Idle keep-alive connections hold a worker until this passes, also when the server stops.
  impl_->server.set_keep_alive_timeout(1);
  // Headers and body go out in separate writes: with Nagle on, the body waits for the client's
  // delayed ACK (40 ms per call on Linux), which would be charged to the adapter.
  impl_->server.set_tcp_nodelay(true);
  // cpp-httplib listens with a backlog of 5: eight adapters connecting at once overflow it, and
  // the kernel answers the overflow with a SYN-ACK retransmit one second later, so a granted
  // call reaches the server a second late. The socket is kept to listen again with room.
  int listening = -1;
  impl_->server.set_socket_options([&listening](socket_t sock) {
    httplib::default_socket_options(sock);
    listening = sock;
  });
  port_ = impl_->server.bind_to_any_port(address);
  if (port_ <= 0) throw std::runtime_error("fake model server: cannot bind " + address);
  if (::listen(listening, SOMAXCONN) != 0) throw std::runtime_error("fake model server: cannot listen on " + address);
  impl_->thread = std::thread([this] { impl_->server.listen_after_bind(); });
  while (!impl_->server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

FakeModelServer::~FakeModelServer() {
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

void FakeModelServer::script(std::vector<Behaviour> behaviours) {
  std::lock_guard lock(impl_->mutex);
  for (auto& b : behaviours) impl_->script.push_back(std::move(b));
}

void FakeModelServer::set_model(Model model) {
  std::lock_guard lock(impl_->mutex);
  impl_->model = std::move(model);
}

void FakeModelServer::enforce_limit(int rpm, std::chrono::milliseconds window) {
  std::lock_guard lock(impl_->mutex);
  impl_->rpm = rpm;
  impl_->window = window;
}

void FakeModelServer::set_latency(std::chrono::milliseconds latency) {
  std::lock_guard lock(impl_->mutex);
  impl_->latency = latency;
}

std::vector<SeenRequest> FakeModelServer::requests() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->seen;
}

int FakeModelServer::answered_429() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->rejected;
}

FakeModelServer::Model oracle_model(const std::map<std::string, std::vector<std::string>>& plans_by_text) {
  return [plans_by_text](const SeenChat& chat) -> std::string {
    if (chat.turns.empty()) return "no conversation";
    const std::string& first = chat.turns.front().second;
    const auto at = first.find("Task: ");
    if (at == std::string::npos) return "I do not see a task.";
    const auto end = first.find('\n', at);
    const std::string text = first.substr(at + 6, end == std::string::npos ? std::string::npos : end - at - 6);
    const auto it = plans_by_text.find(text);
    if (it == plans_by_text.end()) return "I do not know this task.";
    std::size_t step = 0;
    for (const auto& [role, t] : chat.turns) step += role == "assistant" ? 1 : 0;
    const std::string key = step < it->second.size() ? it->second[step] : "0";
    switch (step % 5) {
      case 0: return key;
      case 1: return "Action: " + key;
      case 2: return "```\n" + key + "\n```";
      case 3: return "\"" + key + "\"";
      default: return "I will do this next, because the plan says so.\nAction: `" + key + "`";
    }
  };
}

}  // namespace mtg::testing
