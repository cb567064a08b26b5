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

// Picks from the page: {"p0.item": "o3", "p0.place": "5"}, each for a question the item asks.
std::map<std::string, std::string> picks_from(const json& j, const Item& item) {
  std::map<std::string, std::string> out;
  if (!j.is_object()) throw Error("field 'picks' must be an object");
  for (const auto& [question, key] : j.items()) {
    if (!item.truth.contains(question)) throw Error("task " + item.task_id + " asks no question '" + question + "'");
    if (!key.is_string()) throw Error("pick '" + question + "' must be a key such as \"o3\" (or \"\")");
    const std::string k = key.get<std::string>();
    // Objects are picked by their o<N>; a placement by its number (999: anywhere).
    const bool placement = question.size() > 6 && question.ends_with(".place");
    const std::size_t digits = placement ? 0 : 1;
    const bool well_formed = k.empty() || (k.size() > digits && k.size() <= 8 && (placement || k[0] == 'o') &&
                                           k.find_first_not_of("0123456789", digits) == std::string::npos);
    if (!well_formed) throw Error("pick '" + question + "' is '" + k + "', not a key such as " + (placement ? "5" : "o3"));
    out[question] = k;
  }
  return out;
}

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
  if (j.contains("picks")) a.picks = picks_from(j["picks"], item);
  return a;
}

// The observation each question is asked in.
std::map<std::string, int> asked_in(const Item& item) {
  std::map<std::string, int> out;
  for (const json& q : item.page.value("questions", json::array())) out[q["id"].get<std::string>()] = q["observation"].get<int>();
  return out;
}

// Picks for questions of observations before `revealed` are given: a later observation may show
// their answers (a number in a placement option, a renumbered platform), so they cannot change.
void check_unchanged(const std::map<std::string, std::string>& picks, const AuditStore::Progress& p,
                     const std::map<std::string, int>& asked, int revealed) {
  for (const auto& [question, key] : picks) {
    const auto at = asked.find(question);
    if (at == asked.end()) continue;
    if (at->second > revealed) throw Error("question '" + question + "' is asked in an observation not shown yet");
    const auto given = p.picks.find(question);
    if (at->second < revealed && (given == p.picks.end() || given->second != key)) {
      throw Error("question '" + question + "' was answered before the next observation was shown; it stays '" +
                  (given == p.picks.end() ? std::string() : given->second) + "'");
    }
  }
}

}  // namespace

AuditServer::AuditServer(const std::filesystem::path& dir, std::string rater)
    : store_(dir, false), rater_(std::move(rater)), http_(std::make_unique<httplib::Server>()) {
  if (rater_.empty() || rater_.size() > 64 ||
      rater_.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.") != std::string::npos) {
    throw Error("mtg audit: --rater must be 1-64 letters, digits, '_', '-' or '.', not '" + rater_ + "'");
  }
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
    const auto answers = store_.answers(rater_);
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
                    {"reasons", reasons}, {"rater", rater_}});
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
  // An item's page as far as this rater has gone: its observations are revealed one at a time,
  // and only the questions of the revealed ones are asked.
  auto page_of = [this](const Item& item) {
    json page = item.page;
    const auto answers = store_.answers(rater_);
    const auto answered = answers.find(item.index);
    const int total = static_cast<int>(page["observations"].size());
    AuditStore::Progress p = store_.progress(item.index, rater_);
    if (answered != answers.end()) p.revealed = total - 1;
    json shown = json::array(), questions = json::array();
    for (int k = 0; k <= p.revealed && k < total; ++k) shown.push_back(page["observations"][static_cast<std::size_t>(k)]);
    for (json q : page["questions"]) {
      const int at = q["observation"].get<int>();
      if (at > p.revealed) continue;
      q["locked"] = at < p.revealed || answered != answers.end();
      questions.push_back(std::move(q));
    }
    page["observations"] = shown;
    page["questions"] = questions;
    page["revealed"] = p.revealed;
    page["observations_total"] = total;
    page["picks"] = answered != answers.end() ? json(answered->second.picks) : json(p.picks);
    if (answered != answers.end()) {
      page["answer"] = {{"valid", answered->second.valid},
                        {"reason", answered->second.reason ? to_string(*answered->second.reason) : ""},
                        {"note", answered->second.note},
                        {"picks", answered->second.picks}};
    }
    return page;
  };
  http_->Get(R"(/api/audit/items/(\d+))", guarded([item_of, page_of](const httplib::Request& req, httplib::Response& res) {
    const auto item = item_of(req, res);
    if (!item) return;
    send_json(res, page_of(*item));
  }));
  http_->Post(R"(/api/audit/items/(\d+)/reveal)",
              guarded([this, item_of, page_of](const httplib::Request& req, httplib::Response& res) {
                const auto item = item_of(req, res);
                if (!item) return;
                const json body = json::parse(req.body, nullptr, false);
                if (body.is_discarded() || !body.is_object()) throw Error("the request is not a JSON object");
                if (store_.answers(rater_).count(item->index) != 0) throw Error("task " + item->task_id + " is answered");
                AuditStore::Progress p = store_.progress(item->index, rater_);
                const int total = static_cast<int>(item->page["observations"].size());
                const auto picks = body.contains("picks") ? picks_from(body["picks"], *item) : std::map<std::string, std::string>{};
                check_unchanged(picks, p, asked_in(*item), p.revealed);
                for (const auto& [question, key] : picks) p.picks[question] = key;
                p.revealed = std::min(total - 1, p.revealed + 1);
                store_.put_progress(item->index, rater_, p);
                send_json(res, page_of(*item));
              }));
  http_->Post(R"(/api/audit/items/(\d+)/answer)",
              guarded([this, item_of](const httplib::Request& req, httplib::Response& res) {
                const auto item = item_of(req, res);
                if (!item) return;
                const json body = json::parse(req.body, nullptr, false);
                if (body.is_discarded()) throw Error("the answer is not JSON");
                Answer answer = answer_from(body, *item);
                const auto answers = store_.answers(rater_);
                if (answers.count(item->index) == 0) {
                  // Judged once everything is shown; earlier picks stay as they were given.
                  const AuditStore::Progress p = store_.progress(item->index, rater_);
                  const int total = static_cast<int>(item->page["observations"].size());
                  if (p.revealed < total - 1) {
                    throw Error("show every observation of task " + item->task_id + " before judging it (" +
                                std::to_string(p.revealed + 1) + " of " + std::to_string(total) + " shown)");
                  }
                  check_unchanged(answer.picks, p, asked_in(*item), p.revealed);
                  for (const auto& [question, key] : p.picks) answer.picks.emplace(question, key);
                } else {
                  answer.picks = answers.at(item->index).picks;  // a second save changes the judgement only
                }
                store_.put_answer(item->index, rater_, answer);
                const auto now = store_.answers(rater_);
                json next = nullptr;
                for (const Item& other : store_.items()) {
                  if (now.count(other.index) == 0) {
                    next = other.index;
                    break;
                  }
                }
                send_json(res, {{"ok", true}, {"answered", now.size()}, {"next", next}});
              }));
  // An image only once its observation is revealed to this rater: the later ones show where the
  // episode went, which would answer the earlier questions (issue 55). Names are
  // <item>_<observation>_<n>.png (audit_builder.cc).
  http_->Get(R"(/api/audit/images/((\d+)_(\d+)_\d+\.png))", guarded([this](const httplib::Request& req, httplib::Response& res) {
    int index = -1, observation = -1;
    try {
      index = std::stoi(std::string(req.matches[2]));
      observation = std::stoi(std::string(req.matches[3]));
    } catch (const std::exception&) {
    }
    const auto item = index >= 0 ? store_.item(index) : std::nullopt;
    if (!item) return send_error(res, 404, "no image " + std::string(req.matches[1]));
    const bool answered = store_.answers(rater_).count(index) != 0;
    const int revealed = answered ? static_cast<int>(item->page["observations"].size()) - 1
                                  : store_.progress(index, rater_).revealed;
    if (observation > revealed) return send_error(res, 403, "image " + std::string(req.matches[1]) + " is not revealed yet");
    const std::filesystem::path file = store_.images_dir() / std::string(req.matches[1]);
    std::ifstream in(file, std::ios::binary);
    if (!in) return send_error(res, 404, "no image " + std::string(req.matches[1]));
    std::ostringstream bytes;
    bytes << in.rdbuf();
    res.set_content(bytes.str(), "image/png");
  }));
  // No report here: it lists every rater's misses with the right keys, and this page is a rater's.
  // `mtg audit report DIR` prints it where the audit is run (issue 55).
  http_->set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (res.body.empty()) send_error(res, res.status, "no such page: " + req.path);
  });
}

}  // namespace mtg::orchestrator::audit
