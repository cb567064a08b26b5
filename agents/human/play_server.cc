#include "agents/human/play_server.h"

#include <httplib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "agents/human/exclusive_port.h"
#include "agents/human/json_reply.h"
#include "agents/human/web_assets.h"
#include "core/util/error.h"

namespace mtg::agents {

using nlohmann::json;
using web::send_error;
using web::send_json;

PlayServer::PlayServer(PlayDesk& desk)
    : desk_(desk), http_(std::make_unique<httplib::Server>()), guard_("the play page") {
  web::bind_exclusively(*http_);
  guard_.install(*http_);
  for (const web::Asset& asset : web::play_assets()) {
    const std::string path = asset.path == "index.html" ? "/" : "/" + asset.path;
    http_->Get(path, [&asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(asset.content.data(), asset.content.size(), asset.mime.c_str());
    });
  }
  // ?after=<version>: long poll, answered when the desk changes (or after 20 s).
  http_->Get("/api/play/observation", [this](const httplib::Request& req, httplib::Response& res) {
    json body;
    if (req.has_param("after")) {
      try {
        body = desk_.wait_change(std::stoll(req.get_param_value("after")), 20000);
      } catch (const std::exception&) {
        return send_error(res, 400, "'after' must be a number");
      }
    } else {
      body = desk_.observation();
    }
    send_json(res, body);
  });
  // {"key": "l3"} -> the next observation (or the waiting desk once the episode has ended).
  http_->Post("/api/play/action", [this](const httplib::Request& req, httplib::Response& res) {
    const json in = json::parse(req.body, nullptr, false);
    if (in.is_discarded() || !in.is_object() || !in.contains("key") || !in["key"].is_string()) {
      return send_error(res, 400, "the body must be {\"key\": \"<offered key>\"}");
    }
    const std::int64_t version = desk_.observation()["version"].get<std::int64_t>();
    if (const std::string refused = desk_.act(in["key"].get<std::string>()); !refused.empty()) {
      return send_error(res, 409, refused);
    }
    send_json(res, desk_.wait_change(version, 30000));
  });
  http_->Get(R"(/api/play/image/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
    // \d+ may still be too large for an int: that is no image either.
    const std::string index = req.matches[1];
    const auto img = index.size() <= 6 ? desk_.image(std::stoi(index)) : std::nullopt;
    if (!img) return send_error(res, 404, "no image " + index.substr(0, 12) + " in the current observation");
    res.set_content(reinterpret_cast<const char*>(img->second.data()), img->second.size(),
                    img->first == "jpeg" ? "image/jpeg" : "image/png");
  });
}

PlayServer::~PlayServer() {
  http_->stop();
  if (thread_.joinable()) thread_.join();
}

void PlayServer::start(const std::string& host, int port, const std::string& token) {
  guard_.set_address({host, port, token});
  if (!http_->bind_to_port(host, port)) {
    throw Error("the play page cannot listen on " + host + ":" + std::to_string(port) +
                " (taken? choose another with --port)");
  }
  thread_ = std::thread([this] { http_->listen_after_bind(); });
}

void PlayServer::start_unix(const std::string& path, const std::string& host, int port, const std::string& token) {
  guard_.set_address({host, port, token});
  ::unlink(path.c_str());  // one left by a killed run
  http_->set_address_family(AF_UNIX);
  if (!http_->bind_to_port(path, 80)) throw Error("the play page cannot listen on the socket " + path);
  ::chmod(path.c_str(), 0600);
  thread_ = std::thread([this] { http_->listen_after_bind(); });
}

}  // namespace mtg::agents
