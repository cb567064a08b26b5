#include "agents/human/play_server.h"

#include <httplib.h>

#include "agents/human/exclusive_port.h"

#include "agents/human/web_assets.h"
#include "core/util/error.h"

namespace mtg::agents {

using nlohmann::json;

PlayServer::PlayServer(PlayDesk& desk) : desk_(desk), http_(std::make_unique<httplib::Server>()) {
  web::bind_exclusively(*http_);
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
        res.status = 400;
        return res.set_content(json{{"error", "'after' must be a number"}}.dump(), "application/json");
      }
    } else {
      body = desk_.observation();
    }
    res.set_content(body.dump(), "application/json");
  });
  // {"key": "l3"} -> the next observation (or the waiting desk once the episode has ended).
  http_->Post("/api/play/action", [this](const httplib::Request& req, httplib::Response& res) {
    const json in = json::parse(req.body, nullptr, false);
    if (in.is_discarded() || !in.is_object() || !in.contains("key") || !in["key"].is_string()) {
      res.status = 400;
      return res.set_content(json{{"error", "the body must be {\"key\": \"<offered key>\"}"}}.dump(),
                             "application/json");
    }
    const std::int64_t version = desk_.observation()["version"].get<std::int64_t>();
    if (const std::string refused = desk_.act(in["key"].get<std::string>()); !refused.empty()) {
      res.status = 409;
      return res.set_content(json{{"error", refused}}.dump(), "application/json");
    }
    res.set_content(desk_.wait_change(version, 30000).dump(), "application/json");
  });
  http_->Get(R"(/api/play/image/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
    const auto img = desk_.image(std::stoi(req.matches[1]));
    if (!img) {
      res.status = 404;
      return res.set_content(json{{"error", "no such image in the current observation"}}.dump(), "application/json");
    }
    res.set_content(reinterpret_cast<const char*>(img->second.data()), img->second.size(),
                    img->first == "jpeg" ? "image/jpeg" : "image/png");
  });
}

PlayServer::~PlayServer() {
  http_->stop();
  if (thread_.joinable()) thread_.join();
}

void PlayServer::start(const std::string& host, int port) {
  if (!http_->bind_to_port(host, port)) {
    throw Error("the play page cannot listen on " + host + ":" + std::to_string(port) +
                " (taken? choose another with --port)");
  }
  thread_ = std::thread([this] { http_->listen_after_bind(); });
}

}  // namespace mtg::agents
