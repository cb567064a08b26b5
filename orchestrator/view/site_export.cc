#include "orchestrator/view/site_export.h"

#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <set>
#include <string>

#include "agents/vlm/encoding.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "orchestrator/report/compare.h"
#include "orchestrator/report/sankey.h"
#include "orchestrator/view/run_view.h"
#include "orchestrator/view/viewer_assets.h"

namespace mtg::web {
extern const char* const kViewerStaticJs;  // page/static_api.js (mtg_embed_text)
}

namespace mtg::orchestrator::view {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class SiteWriter {
 public:
  explicit SiteWriter(fs::path root) : root_(std::move(root)) {}

  void text(const std::string& rel, std::string_view content) {
    const fs::path file = root_ / rel;
    fs::create_directories(file.parent_path());
    std::ofstream out(file, std::ios::binary);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    if (!out.flush()) throw Error("cannot write " + file.string());
    stats.bytes += content.size();
  }
  /// A data file the page loads with <script>: mtgPut("<rel>", <value>).
  void data(const std::string& rel, const json& value) {
    text(rel, "mtgPut(" + json(rel).dump() + ", " +
                  value.dump(-1, ' ', false, json::error_handler_t::replace) + ");\n");
  }
  /// The image's file (written once per content); its path from the page.
  std::string image(const RecordedImage& img) {
    const std::string rel = "img/" +
                            vlm::sha256_hex({reinterpret_cast<const char*>(img.bytes.data()), img.bytes.size()}) +
                            (img.encoding == "jpeg" ? ".jpg" : ".png");
    ++stats.image_refs;
    if (written_.insert(rel).second) {
      text(rel, {reinterpret_cast<const char*>(img.bytes.data()), img.bytes.size()});
      ++stats.images;
    }
    return rel;
  }

  ExportStats stats;

 private:
  fs::path root_;
  std::set<std::string> written_;
};

void require_empty(const fs::path& out) {
  std::error_code ec;
  if (!fs::exists(out, ec)) {
    // Only the site's own folder is made: a typo in its parent must not build a tree elsewhere.
    fs::path site = fs::absolute(out).lexically_normal();
    if (!site.has_filename()) site = site.parent_path();  // "site/"
    const fs::path parent = site.parent_path();
    if (!fs::is_directory(parent, ec)) throw Error(out.string() + ": its folder " + parent.string() + " does not exist");
    return;
  }
  if (!fs::is_directory(out, ec)) throw Error(out.string() + " is a file: name a new or empty folder to export into");
  if (!fs::is_empty(out, ec)) throw Error(out.string() + " is not empty: name a new or empty folder to export into");
}

// One episode: every recorded attempt with its images and goal (the viewer's "Show the goal").
json episode_file(RunView& view, SiteWriter& site, const EpisodeRow& row) {
  const bus::EpisodeId id = row.episode_id;
  json latest = view.episode(id, -1);
  json file = {{"attempt", row.attempt}, {"attempts", json::object()}, {"truth", json::object()}};
  std::vector<int> attempts;
  for (const auto& k : latest["attempts"]) attempts.push_back(k.get<int>());
  if (attempts.empty()) attempts.push_back(latest["attempt"].get<int>());  // a row without a recording
  for (const int k : attempts) {
    json e = k == latest["attempt"].get<int>() ? latest : view.episode(id, k);
    const auto images = view.images(id, k);
    link_images(e, [&](int step, int index) {
      const auto it = images.find({step, index});
      return it == images.end() ? std::string() : site.image(it->second);
    });
    const std::string key = std::to_string(k);
    try {
      file["truth"][key] = view.truth(id, k);
    } catch (const Error& missing) {  // a run copied without its truth.key: the pages, without the goals
      if (site.stats.truths_missing++ == 0) log::warn("goals left out of the export: " + std::string(missing.what()));
      file["truth"][key] = nullptr;
    }
    file["attempts"][key] = std::move(e);
    ++site.stats.attempts;
  }
  return file;
}

ExportStats write_site(const std::vector<fs::path>& runs, const fs::path& out,
                       const std::function<void(std::size_t, std::size_t)>& progress);

}  // namespace

ExportStats export_site(const std::vector<fs::path>& runs, const fs::path& out,
                        const std::function<void(std::size_t, std::size_t)>& progress) {
  if (runs.empty()) throw Error("name at least one run folder to export");
  require_empty(out);
  // A failed export leaves no half site behind (the folder was new or empty).
  try {
    return write_site(runs, out, progress);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(out, ec);
    throw;
  }
}

namespace {

// A shared site keeps what made the run (provenance) but not where its files lived: every
// absolute path in it (the command's arguments, the task set, the sessions' commands) becomes its
// file name.
void without_folders(json& summary) {
  auto name_only = [](json& text) {
    if (text.is_string() && !text.get<std::string>().empty() && text.get<std::string>().front() == '/') {
      text = fs::path(text.get<std::string>()).filename().string();
    }
  };
  auto command = [&](json& argv) {
    if (!argv.is_array()) return;
    for (json& arg : argv) name_only(arg);
  };
  if (summary.contains("settings")) name_only(summary["settings"]["tasks_db"]);
  if (summary.contains("provenance") && summary["provenance"].is_object()) {
    json& p = summary["provenance"];
    command(p["command"]);
    if (p.contains("task_set")) name_only(p["task_set"]["file"]);
  }
  if (summary.contains("sessions")) {
    for (json& s : summary["sessions"]) {
      if (s.contains("command")) command(s["command"]);
    }
  }
}

// The comparisons the overview offers (each agent of a run as the baseline; each run against each
// other one), computed now: data/comparisons.js maps the query ("a=R&baseline=X", "a=R&b=S") to
// its file. A pair that cannot be compared (no common task or agent) is left out.
void write_comparisons(SiteWriter& site, const std::vector<std::unique_ptr<RunView>>& views) {
  json keys = json::object();
  auto put = [&](const std::string& key, const std::function<json()>& compare) {
    try {
      const json value = compare();
      const std::string file = "data/compare-" + std::to_string(keys.size()) + ".js";
      site.data(file, value);
      keys[key] = file;
    } catch (const std::exception&) {  // a pair that cannot be compared: the page says so when asked
    }
  };
  std::vector<RunRows> runs;
  for (std::size_t r = 0; r < views.size(); ++r) runs.push_back(views[r]->compare_rows());
  for (const RunRows& a : runs) {
    std::set<std::string> agents;
    for (const EpisodeRow& row : a.rows) agents.insert(row.agent);
    if (agents.size() < 2) continue;
    for (const std::string& base : agents) {
      put("a=" + a.name + "&baseline=" + base, [&] { return compare_runs(a, nullptr, "", base); });
    }
  }
  for (const RunRows& a : runs) {
    for (const RunRows& b : runs) {
      if (&a != &b) put("a=" + a.name + "&b=" + b.name, [&] { return compare_runs(a, &b, "", ""); });
    }
  }
  site.data("data/comparisons.js", keys);
  std::vector<LeaderboardRun> boards;
  for (const auto& v : views) boards.push_back(v->leaderboard_run());
  site.data("data/leaderboard.js", make_leaderboard(boards));
}

ExportStats write_site(const std::vector<fs::path>& runs, const fs::path& out,
                       const std::function<void(std::size_t, std::size_t)>& progress) {
  std::vector<std::unique_ptr<RunView>> views;
  const auto names = run_names(runs);
  for (std::size_t i = 0; i < runs.size(); ++i) views.push_back(std::make_unique<RunView>(names[i], runs[i]));
  std::vector<std::vector<EpisodeRow>> rows;
  std::size_t total = 0;
  for (auto& v : views) {
    rows.push_back(v->all_rows());
    total += rows.back().size();
  }

  SiteWriter site(out);
  // The viewer's own page, reading the data files instead of the server.
  for (const auto& asset : web::viewer_assets()) {
    std::string content(asset.content);
    if (asset.path == "index.html") {
      const std::string viewer = "<script src=\"viewer.js\"></script>";
      const auto at = content.find(viewer);
      if (at == std::string::npos) throw InternalError("the viewer page does not load viewer.js");
      content.insert(at, "<script src=\"static_api.js\"></script>\n");
    }
    site.text(asset.path, content);
  }
  site.text("static_api.js", web::kViewerStaticJs);

  json index = json::array();
  std::size_t done = 0;
  for (std::size_t r = 0; r < views.size(); ++r) {
    RunView& view = *views[r];
    const std::string dir = "data/r" + std::to_string(r) + "/";
    // The recordings read to their end first, so the pages and the command name the same damage
    // (the indexer thread may not have got there yet).
    const std::vector<std::string> damage = view.damage_read_through();
    json overview = view.overview();
    // A snapshot: the exported page never polls; and where the run lived here is nobody's business.
    overview["live"] = false;
    overview.erase("dir");
    without_folders(overview);
    json summary = view.summary();
    summary["live"] = false;
    summary.erase("dir");
    without_folders(summary);
    json agents = json::array();
    for (const auto& [agent, _] : overview["report"]["by_agent"].items()) agents.push_back(agent);
    index.push_back({{"summary", summary}, {"dir", "r" + std::to_string(r)}, {"agents", agents}});
    site.data(dir + "run.js", overview);
    site.data(dir + "sankey.js", sankey_svg(overview["report"]["sankey"], kSankeyWidth, kSankeyHeight));
    for (std::size_t a = 0; a < agents.size(); ++a) {
      const json report = view.agent_report(agents[a].get<std::string>());
      site.data(dir + "report-" + std::to_string(a) + ".js", report);
      site.data(dir + "sankey-" + std::to_string(a) + ".js", sankey_svg(report["sankey"], kSankeyWidth, kSankeyHeight));
    }
    for (const EpisodeRow& row : rows[r]) {
      site.data(dir + "episodes/" + to_string(row.episode_id) + ".js", episode_file(view, site, row));
      ++site.stats.episodes;
      if (progress) progress(++done, total);
    }
    // After the episodes: each was read, so the recording is indexed and what agents said is
    // there for the page's search, as the server searches it.
    json list = view.episodes(EpisodeQuery{}, 0, std::numeric_limits<std::size_t>::max())["rows"];
    for (json& row : list) {
      std::string said = view.said_of(bus::EpisodeId(row["episode_id"].get<std::int64_t>()));
      if (!said.empty()) row["said"] = std::move(said);
    }
    site.data(dir + "rows.js", list);
    site.data(dir + "marks.js", view.marks());  // shown, not changed: a site has no server to keep them
    // What the viewer names (damaged stretches, missing or altered recordings): said by the
    // command too, not only on the exported page (issue 55).
    for (const std::string& line : damage) site.stats.damage.push_back(view.name() + ": " + line);
    ++site.stats.runs;
  }
  site.data("data/runs.js", index);
  write_comparisons(site, views);
  return site.stats;
}

}  // namespace

}  // namespace mtg::orchestrator::view
