#include "orchestrator/audit/audit_server.h"

#include <httplib.h>

#include <fstream>
#include <sstream>

#include "agents/human/exclusive_port.h"
#include "agents/human/json_reply.h"
#include "agents/human/web_assets.h"
#include "core/util/error.h"
#include "orchestrator/audit/audit_report.h"

namespace mtg::web {
const std::vector<Asset>& audit_assets();
}

namespace mtg::orchestrator::audit {
namespace {

using nlohmann::json;

using web::send_error;
using web::send_json;

// An answer from the page: {"valid": bool, "reason": "...", "note": "...", "picks": {"p0.item": "o3"}}.
Answer answer_from(const json& j, const Item& item) {
  if (!j.is_object()) throw Error("the answer must be a JSON object");
  if (!j.contains("valid") || !j["valid"].is_boolean()) throw Error("field 'valid' must be true or false");
  Answer a;
  a.valid = j["valid"].get<bool>();
  if (!a.valid) {
    if (!j.contains("reason") || !j["reason"].is_string()) throw Error("an invalid task needs a 'reason'");
    a.reason = reason_from_string(j["reason"].get<std::string>());
  }
  if (j.contains("note")) {
    if (!j["note"].is_string()) throw Error("field 'note' must be text");
    a.note = j["note"].get<std::string>().substr(0, 2000);
  }
  if (j.contains("picks")) {
    if (!j["picks"].is_object()) throw Error("field 'picks' must be an object");
    for (const auto& [question, key] : j["picks"].items()) {
      if (!item.truth.contains(question)) throw Error("task " + item.task_id + " asks no question '" + question + "'");
      if (!key.is_string()) throw Error("pick '" + question + "' must be a key such as \"o3\" (or \"\")");
      const std::string k = key.get<std::string>();
      const bool well_formed = k.empty() || (k.size() >= 2 && k[0] == 'o' &&
                                             k.find_first_not_of("0123456789", 1) == std::string::npos);
      if (!well_formed) throw Error("pick '" + question + "' is '" + k + "', not a key such as o3");
      a.picks[question] = k;
    }
  }
  return a;
}

}  // namespace

AuditServer::AuditServer(const std::filesystem::path& dir)
    : store_(dir, false), http_(std::make_unique<httplib::Server>()) {
  if (store_.meta().count("format") == 0) {
    throw Error(dir.string() + " holds no finished audit (make it with mtg audit --tasks ... --out " + dir.string() + ")");
  }
  web::bind_exclusively(*http_);
  add_routes();
}

AuditServer::~AuditServer() = default;

int AuditServer::bind(const std::string& host, int port) {
  const int bound = port == 0 ? http_->bind_to_any_port(host) : (http_->bind_to_port(host, port) ? port : -1);
  if (bound <= 0) throw Error("mtg audit: cannot listen on " + host + ":" + std::to_string(port) + " (taken?)");
  guard_.set_address({host, bound, web::is_loopback(host) ? "" : web::random_token()});
  return bound;
}

void AuditServer::serve() { http_->listen_after_bind(); }
void AuditServer::stop() { http_->stop(); }

void AuditServer::add_routes() {
  guard_.install(*http_);
  for (const web::Asset& asset : web::audit_assets()) {
    const std::string path = asset.path == "index.html" ? "/" : "/" + asset.path;
    http_->Get(path, [&asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(asset.content.data(), asset.content.size(), asset.mime.c_str());
    });
  }
  auto guarded = [this](std::function<void(const httplib::Request&, httplib::Response&)> fn) {
    return [this, fn = std::move(fn)](const httplib::Request& req, httplib::Response& res) {
      const std::lock_guard lock(mutex_);
      try {
        fn(req, res);
      } catch (const std::exception& e) {
        send_error(res, 400, e.what());
      }
    };
  };
  http_->Get("/api/audit", guarded([this](const httplib::Request&, httplib::Response& res) {
    const auto answers = store_.answers();
    json items = json::array();
    for (const Item& item : store_.items()) {
      items.push_back({{"index", item.index}, {"task_id", item.task_id}, {"level", item.level},
                       {"answered", answers.count(item.index) != 0}});
    }
    json reasons = json::array();
    for (const Reason r : all_reasons()) reasons.push_back(to_string(r));
    json meta = json::object();
    for (const auto& [k, v] : store_.meta()) meta[k] = v;
    send_json(res, {{"meta", meta}, {"items", items}, {"answered", answers.size()}, {"total", items.size()},
                    {"reasons", reasons}});
  }));
  auto item_of = [this](const httplib::Request& req, httplib::Response& res) -> std::optional<Item> {
    int index = -1;
    try {
      index = std::stoi(std::string(req.matches[1]));
    } catch (const std::exception&) {
    }
    auto item = index >= 0 ? store_.item(index) : std::nullopt;
    if (!item) send_error(res, 404, "no task " + std::string(req.matches[1]) + " in this audit");
    return item;
  };
  http_->Get(R"(/api/audit/items/(\d+))", guarded([this, item_of](const httplib::Request& req, httplib::Response& res) {
    const auto item = item_of(req, res);
    if (!item) return;
    json page = item->page;
    const auto answers = store_.answers();
    if (const auto it = answers.find(item->index); it != answers.end()) {
      page["answer"] = {{"valid", it->second.valid},
                        {"reason", it->second.reason ? to_string(*it->second.reason) : ""},
                        {"note", it->second.note},
                        {"picks", it->second.picks}};
    }
    send_json(res, page);
  }));
  http_->Post(R"(/api/audit/items/(\d+)/answer)",
              guarded([this, item_of](const httplib::Request& req, httplib::Response& res) {
                const auto item = item_of(req, res);
                if (!item) return;
                const json body = json::parse(req.body, nullptr, false);
                if (body.is_discarded()) throw Error("the answer is not JSON");
                store_.put_answer(item->index, answer_from(body, *item));
                const auto answers = store_.answers();
                json next = nullptr;
                for (const Item& other : store_.items()) {
                  if (answers.count(other.index) == 0) {
                    next = other.index;
                    break;
                  }
                }
                send_json(res, {{"ok", true}, {"answered", answers.size()}, {"next", next}});
              }));
  http_->Get(R"(/api/audit/images/([0-9_]+\.png))", guarded([this](const httplib::Request& req, httplib::Response& res) {
    const std::filesystem::path file = store_.images_dir() / std::string(req.matches[1]);
    std::ifstream in(file, std::ios::binary);
    if (!in) return send_error(res, 404, "no image " + std::string(req.matches[1]));
    std::ostringstream bytes;
    bytes << in.rdbuf();
    res.set_content(bytes.str(), "image/png");
  }));
  http_->Get("/api/audit/report", guarded([this](const httplib::Request&, httplib::Response& res) {
    send_json(res, make_report(store_.items(), store_.answers()).to_json());
  }));
  http_->set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (res.body.empty()) send_error(res, res.status, "no such page: " + req.path);
  });
}

}  // namespace mtg::orchestrator::audit
