#include "orchestrator/view/view_server.h"

#include <httplib.h>

#include "agents/human/exclusive_port.h"
#include "agents/human/json_reply.h"

#include <functional>
#include <map>
#include <optional>

#include "orchestrator/view/viewer_assets.h"
#include "core/util/error.h"
#include "orchestrator/report/compare.h"
#include "orchestrator/run/provenance.h"
#include "orchestrator/report/sankey.h"

namespace mtg::orchestrator::view {
namespace {

using nlohmann::json;

using web::send_error;
using web::send_json;

std::optional<std::string> param(const httplib::Request& req, const char* name) {
  if (!req.has_param(name) || req.get_param_value(name).empty()) return std::nullopt;
  return req.get_param_value(name);
}

int int_param(const httplib::Request& req, const char* name, int fallback) {
  const auto v = param(req, name);
  if (!v) return fallback;
  try {
    std::size_t used = 0;
    const int n = std::stoi(*v, &used);
    if (used == v->size()) return n;
  } catch (const std::exception&) {
  }
  throw Error(std::string("query parameter '") + name + "' is not a number: " + *v);
}

// The attempt asked for, or -1 (the latest) when none is: a negative one is a mistake of the
// request, not the latest.
int attempt_param(const httplib::Request& req) {
  if (!param(req, "attempt")) return -1;
  const int attempt = int_param(req, "attempt", -1);
  if (attempt < 0) throw Error("query parameter 'attempt' must be 0 or more, not " + std::to_string(attempt));
  return attempt;
}

// A number matched by \d+ in the route; one too large is a mistake of the request, said so.
long long path_number(const httplib::Request& req, std::size_t match, const char* what) {
  const std::string text = req.matches[match];
  try {
    return std::stoll(text);
  } catch (const std::exception&) {
    throw Error(std::string(what) + " '" + text.substr(0, 24) + "' is out of range");
  }
}

EpisodeQuery query_of(const httplib::Request& req);

EpisodeFilter filter_of(const httplib::Request& req) {
  EpisodeFilter f;
  f.agent = param(req, "agent");
  f.scene = param(req, "scene");
  f.task = param(req, "task");
  f.cause = param(req, "cause");
  f.stage = param(req, "stage");
  f.status = param(req, "status");
  if (param(req, "level")) f.level = int_param(req, "level", 0);
  if (const auto s = param(req, "success")) {
    if (*s != "1" && *s != "0" && *s != "true" && *s != "false") {
      throw Error("query parameter 'success' must be 1 or 0, not " + *s);
    }
    f.success = *s == "1" || *s == "true";
  }
  return f;
}

// The list's filters, search (q) and order (sort, order=asc|desc).
EpisodeQuery query_of(const httplib::Request& req) {
  EpisodeQuery q;
  q.filter = filter_of(req);
  q.text = param(req, "q");
  if (const auto sort = param(req, "sort")) q.sort = *sort;
  if (const auto order = param(req, "order")) {
    if (*order != "asc" && *order != "desc") throw Error("query parameter 'order' must be asc or desc, not " + *order);
    q.descending = *order == "desc";
  }
  return q;
}

// Every handler answers a bad request with one JSON error line instead of a dropped connection.
httplib::Server::Handler guarded(std::function<void(const httplib::Request&, httplib::Response&)> fn) {
  return [fn = std::move(fn)](const httplib::Request& req, httplib::Response& res) {
    try {
      fn(req, res);
    } catch (const std::exception& e) {
      send_error(res, 400, e.what());
    }
  };
}

}  // namespace

ViewServer::ViewServer(const std::vector<std::filesystem::path>& run_dirs) : http_(std::make_unique<httplib::Server>()) {
  web::bind_exclusively(*http_);
  guard_.install(*http_);
  const auto names = run_names(run_dirs);
  for (std::size_t i = 0; i < run_dirs.size(); ++i) runs_.push_back(std::make_unique<RunView>(names[i], run_dirs[i]));
  add_routes();
}

ViewServer::~ViewServer() = default;

RunView* ViewServer::run(const std::string& name) {
  for (const auto& r : runs_) {
    if (r->name() == name) return r.get();
  }
  return nullptr;
}

void ViewServer::add_routes() {
  for (const web::Asset& asset : web::viewer_assets()) {
    const std::string path = asset.path == "index.html" ? "/" : "/" + asset.path;
    http_->Get(path, [&asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(asset.content.data(), asset.content.size(), asset.mime.c_str());
    });
  }
  http_->Get("/api/runs", guarded([this](const httplib::Request&, httplib::Response& res) {
    json list = json::array();
    for (const auto& r : runs_) list.push_back(r->summary());
    send_json(res, list);
  }));
  // A paired comparison (mtg compare): ?a=<run>[&b=<run>][&agent=A][&baseline=B].
  http_->Get("/api/compare", guarded([this](const httplib::Request& req, httplib::Response& res) {
    auto rows_of = [this](const std::string& name) {
      RunView* r = run(name);
      if (r == nullptr) throw Error("no run named '" + name + "'");
      return r->compare_rows();
    };
    const auto a = param(req, "a");
    if (!a) throw Error("query parameter 'a' (the baseline run) is required");
    const RunRows first = rows_of(*a);
    std::optional<RunRows> second;
    if (const auto b = param(req, "b")) second = rows_of(*b);
    send_json(res, compare_runs(first, second ? &*second : nullptr, param(req, "agent").value_or(""),
                                param(req, "baseline").value_or("")));
  }));
  // The runs' agents ranked per suite, with ties (mtg leaderboard).
  http_->Get("/api/leaderboard", guarded([this](const httplib::Request&, httplib::Response& res) {
    std::vector<LeaderboardRun> runs;
    for (const auto& r : runs_) runs.push_back(r->leaderboard_run());
    send_json(res, make_leaderboard(runs));
  }));
  // Every other route names a run first; an unknown one is a 404 with its name.
  auto with_run = [this](std::function<void(RunView&, const httplib::Request&, httplib::Response&)> fn) {
    return guarded([this, fn = std::move(fn)](const httplib::Request& req, httplib::Response& res) {
      RunView* r = run(req.matches[1]);
      if (r == nullptr) return send_error(res, 404, "no run named '" + std::string(req.matches[1]) + "'");
      fn(*r, req, res);
    });
  };
  http_->Get(R"(/api/runs/([^/]+))", with_run([](RunView& r, const httplib::Request&, httplib::Response& res) {
    send_json(res, r.overview());
  }));
  // ?agent=A: one agent's episodes only (the overview's failure section, per agent).
  const auto report_for = [](RunView& r, const httplib::Request& req) -> json {
    const auto agent = param(req, "agent");
    if (!agent) return r.overview()["report"];
    json report = r.agent_report(*agent);
    if (report.is_null()) throw Error("run " + r.name() + " has no episode of agent '" + *agent + "'");
    return report;
  };
  http_->Get(R"(/api/runs/([^/]+)/sankey\.svg)",
             with_run([report_for](RunView& r, const httplib::Request& req, httplib::Response& res) {
               res.set_content(sankey_svg(report_for(r, req)["sankey"], kSankeyWidth, kSankeyHeight), "image/svg+xml");
             }));
  http_->Get(R"(/api/runs/([^/]+)/report)", with_run([report_for](RunView& r, const httplib::Request& req,
                                                                   httplib::Response& res) {
    send_json(res, report_for(r, req));
  }));
  // People's marks: read them (?episode=ID for one episode's trail), or add one (JSON body
  // {episode, action, tag, reason, who}); the guard lets only this page's own requests write.
  http_->Get(R"(/api/runs/([^/]+)/marks)", with_run([](RunView& r, const httplib::Request& req, httplib::Response& res) {
    const auto episode = param(req, "episode");
    send_json(res, r.marks(episode ? bus::EpisodeId(int_param(req, "episode", -1)) : bus::EpisodeId()));
  }));
  http_->Post(R"(/api/runs/([^/]+)/marks)", with_run([](RunView& r, const httplib::Request& req, httplib::Response& res) {
    const json body = json::parse(req.body, nullptr, false);
    if (body.is_discarded() || !body.is_object()) throw Error("a mark is a JSON object");
    auto text = [&body](const char* key) -> std::string {
      if (!body.contains(key)) return "";
      if (!body[key].is_string()) throw Error(std::string("mark: '") + key + "' must be text");
      return body[key].get<std::string>();
    };
    if (!body.contains("episode") || !body["episode"].is_number_integer()) throw Error("mark: 'episode' must be an episode id");
    const auto action = mark_action_from_string(text("action"));
    if (!action) throw Error("mark: 'action' must be one of flag, unflag, tag, untag, exclude, include");
    r.add_mark({bus::EpisodeId(body["episode"].get<std::int64_t>()), *action, text("tag"), text("reason"), text("who"),
                utc_now()});
    send_json(res, r.marks(bus::EpisodeId(body["episode"].get<std::int64_t>())));
  }));
  http_->Get(R"(/api/runs/([^/]+)/episodes)", with_run([](RunView& r, const httplib::Request& req,
                                                           httplib::Response& res) {
    const int offset = int_param(req, "offset", 0), limit = int_param(req, "limit", 100);
    if (offset < 0 || limit < 0) throw Error("offset and limit must not be negative");
    send_json(res, r.episodes(query_of(req), static_cast<std::size_t>(offset), static_cast<std::size_t>(limit)));
  }));
  // Where an episode stands in the list the page came from: previous / next on the episode page.
  http_->Get(R"(/api/runs/([^/]+)/episodes/(\d+)/neighbours)", with_run([](RunView& r, const httplib::Request& req,
                                                                            httplib::Response& res) {
    send_json(res, r.neighbours(query_of(req), bus::EpisodeId(path_number(req, 2, "episode"))));
  }));
  http_->Get(R"(/api/runs/([^/]+)/episodes/(\d+))", with_run([](RunView& r, const httplib::Request& req,
                                                                 httplib::Response& res) {
    const bus::EpisodeId id(path_number(req, 2, "episode"));
    json e = r.episode(id, attempt_param(req));
    if (e.is_null()) return send_error(res, 404, "run " + r.name() + " has no episode " + to_string(id));
    const std::string base = "/api/runs/" + r.name() + "/episodes/" + to_string(id) + "/images/" +
                             std::to_string(e["attempt"].get<int>()) + "/";
    link_images(e, [&](int step, int index) { return base + std::to_string(step) + "/" + std::to_string(index); });
    send_json(res, e);
  }));
  http_->Get(R"(/api/runs/([^/]+)/episodes/(\d+)/truth)", with_run([](RunView& r, const httplib::Request& req,
                                                                       httplib::Response& res) {
    const json t = r.truth(bus::EpisodeId(path_number(req, 2, "episode")), attempt_param(req));
    if (t.is_null()) return send_error(res, 404, "no goal recorded for that episode");
    send_json(res, t);
  }));
  http_->Get(R"(/api/runs/([^/]+)/episodes/(\d+)/images/(\d+)/(\d+)/(\d+))",
             with_run([](RunView& r, const httplib::Request& req, httplib::Response& res) {
               const auto small = [&](std::size_t m, const char* what) {
                 const long long n = path_number(req, m, what);
                 if (n > 1000000) throw Error(std::string(what) + " " + std::to_string(n) + " is out of range");
                 return static_cast<int>(n);
               };
               const auto img = r.image(bus::EpisodeId(path_number(req, 2, "episode")), small(3, "attempt"),
                                        small(4, "step"), small(5, "image"));
               if (!img) return send_error(res, 404, "no such image in the recording");
               res.set_header("Cache-Control", "max-age=86400");
               res.set_content(reinterpret_cast<const char*>(img->bytes.data()), img->bytes.size(),
                               img->encoding == "jpeg" ? "image/jpeg" : "image/png");
             }));
}

int ViewServer::bind(const std::string& host, int port) {
  if (port == 0) {
    port = http_->bind_to_any_port(host);
    if (port <= 0) throw Error("cannot listen on " + host);
  } else if (!http_->bind_to_port(host, port)) {
    throw Error("cannot listen on " + host + ":" + std::to_string(port) + " (taken? choose another with --port)");
  }
  guard_.set_address({host, port, web::is_loopback(host) ? "" : web::random_token()});
  return port;
}

void ViewServer::serve() { http_->listen_after_bind(); }
void ViewServer::stop() { http_->stop(); }

}  // namespace mtg::orchestrator::view
