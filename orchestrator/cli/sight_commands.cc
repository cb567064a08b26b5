#include "orchestrator/cli/sight_commands.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgproc.hpp>
#include <ostream>

#include "core/render/gl/scene_renderer.h"
#include "core/render/image_codec.h"
#include "core/render/image_renderer.h"
#include "core/render/mark_layout.h"
#include "core/render/sight_labels.h"
#include "core/render/view.h"
#include "core/render/visibility.h"
#include "core/tasks/referring.h"
#include "core/util/agreement.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/json_file.h"

namespace mtg::cli {

namespace fs = std::filesystem;

namespace {

// Every object on a navigable platform in the view from each side the robot can stand at, with
// what that view shows of it (objects outside the picture left out).
std::vector<render::SightCase> candidates(const std::string& scene, const graph::SceneGraph& g,
                                          const render::SceneGeometry& geometry) {
  const episode::WorldState s = episode::initial_state(g);
  const render::VisibilityOptions rule;
  const double pixel_area = static_cast<double>(rule.pass_scale) * rule.pass_scale;
  std::vector<render::SightCase> out;
  for (const graph::PlatformId p : g.navigable) {
    const std::vector<graph::ObjectId> on = episode::everything_on(g, s, p);
    if (on.empty()) continue;
    for (int side = 0; side < 4; ++side) {
      if (!g.platforms[p].sides[static_cast<std::size_t>(side)].usable()) continue;
      const render::Camera camera = render::platform_camera(g, s, p, side, rule.image_width, rule.image_height);
      const render::Camera pass = render::at_resolution(camera, rule.pass_width(), rule.pass_height());
      const render::IdView ids = render::draw_id_view(g, geometry, s, pass);
      for (const graph::ObjectId o : on) {
        const auto it = std::find_if(ids.objects.begin(), ids.objects.end(), [&](const render::ObjectSight& x) {
          return x.object == static_cast<std::int32_t>(o.index());
        });
        if (it == ids.objects.end() || it->silhouette == 0) continue;
        render::SightCase c;
        c.scene = scene;
        c.platform = g.platforms[p].name;
        c.side = side;
        c.object = g.objects[o].name;
        c.noun = tasks::noun_of(g.objects[o], tasks::Ambiguity::kNoun);
        c.camera = camera;
        c.visible_pixels = it->visible * pixel_area;
        c.silhouette_pixels = it->silhouette * pixel_area;
        // The arrow points where the object's number would sit: its deepest visible pixel (or
        // its top, projected, when nothing of it shows).
        const episode::ObjectState& st = s.objects[o];
        const geom::Point2 centre = episode::footprint_centre(st);
        const render::ItemMark mark{1, o, Eigen::Vector3d(centre.x(), centre.y(), st.top)};
        const render::MarkLayout layout = render::layout_item_marks(ids.image, rule.pass_scale, camera, {mark});
        if (layout.placed.empty()) continue;  // its anchor is outside the picture
        c.arrow_tip = layout.placed.front().anchor;
        out.push_back(std::move(c));
      }
    }
  }
  return out;
}

// An arrow from outside the object to just short of `tip`, from the free diagonal.
void draw_arrow(cv::Mat& image, const Eigen::Vector2d& tip) {
  const Eigen::Vector2d directions[] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
  constexpr double kLength = 70.0, kGap = 5.0;
  for (const Eigen::Vector2d& d0 : directions) {
    const Eigen::Vector2d d = d0.normalized();
    const Eigen::Vector2d tail = tip + d * (kLength + kGap);
    if (tail.x() < 4 || tail.y() < 4 || tail.x() > image.cols - 5 || tail.y() > image.rows - 5) continue;
    const Eigen::Vector2d head = tip + d * kGap;
    const cv::Point a(static_cast<int>(std::lround(tail.x())), static_cast<int>(std::lround(tail.y())));
    const cv::Point b(static_cast<int>(std::lround(head.x())), static_cast<int>(std::lround(head.y())));
    cv::arrowedLine(image, a, b, cv::Scalar(0, 0, 0), 6, cv::LINE_AA, 0, 0.3);
    cv::arrowedLine(image, a, b, cv::Scalar(255, 0, 255), 3, cv::LINE_AA, 0, 0.3);
    return;
  }
}

std::string case_id(std::size_t k) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "s%03zu", k + 1);
  return buf;
}

// Where a draw's key lives: the one given, else beside the raters' folder, "<folder>-key.json".
fs::path key_path(const std::string& given, const fs::path& folder) {
  if (!given.empty()) return given;
  fs::path f = fs::absolute(folder).lexically_normal();
  if (!f.has_filename()) f = f.parent_path();
  return f.parent_path() / (f.filename().string() + "-key.json");
}

}  // namespace

int run_sights_draw(const SightsDrawOptions& o) {
  if (o.scenes.empty() || o.out.empty()) throw Error("mtg audit sights: --scene <name> and --out <folder> are required");
  if (o.count < 1) throw Error("mtg audit sights: --count must be at least 1, not " + std::to_string(o.count));
  const fs::path out(o.out);
  if (fs::exists(out / "sights.json")) throw Error("mtg audit sights: " + o.out + " holds a draw already (sights.json)");
  // The answers (which object, its noun, its pixels) stay out of the folder raters are given
  // (issue 55: sights.json once held them beside the raters' labels).
  const fs::path key = key_path(o.key, out);
  const fs::path folder = fs::absolute(out).lexically_normal();
  const fs::path inside = fs::absolute(key).lexically_normal().lexically_relative(folder);
  if (!inside.empty() && *inside.begin() != "..") {
    throw Error("mtg audit sights: --key " + key.string() + " lies inside the raters' folder " + o.out + "; put it elsewhere");
  }
  fs::create_directories(out / "images");
  fs::create_directories(out / "labels");
  render::ImageRenderer renderer(o.profile);
  std::vector<render::SightCase> all;
  for (const std::string& scene : o.scenes) {
    const graph::SceneCache::Entry& entry = renderer.scenes().load(scene, o.data_dir);
    std::vector<render::SightCase> c = candidates(scene, entry.graph, renderer.geometry(entry));
    std::fprintf(stderr, "%s: %zu objects in %zu platform views\n", scene.c_str(), c.size(), entry.graph.navigable.size());
    all.insert(all.end(), c.begin(), c.end());
  }
  const std::vector<std::size_t> drawn = render::stratified_draw(all, static_cast<std::size_t>(o.count), o.seed);
  nlohmann::json cases = nlohmann::json::array(), shown = nlohmann::json::array();
  for (std::size_t k = 0; k < drawn.size(); ++k) {
    render::SightCase& c = all[drawn[k]];
    c.id = case_id(k);
    const graph::SceneCache::Entry& entry = renderer.scenes().load(c.scene, o.data_dir);
    const episode::WorldState s = episode::initial_state(entry.graph);
    render::ViewPlan plan;
    plan.camera = c.camera;
    plan.side = c.side;
    render::ViewImages images =
        render::draw_view(renderer.scene_renderer(entry), entry.graph, s, plan, false, renderer.geometry(entry));
    draw_arrow(images.plain, c.arrow_tip);
    const std::vector<std::vector<std::uint8_t>> png = render::encode_images({&images.plain}, "png", 1);
    const fs::path file = out / "images" / (c.id + ".png");
    write_file_atomically(file.string(), [&](std::ostream& os) {
      os.write(reinterpret_cast<const char*>(png.front().data()), static_cast<std::streamsize>(png.front().size()));
    });
    nlohmann::json j = render::to_json(c);
    j["image"] = "images/" + c.id + ".png";
    cases.push_back(j);
    shown.push_back({{"id", c.id}, {"image", j["image"]}});
  }
  const nlohmann::json doc = {{"format", "mtg-sights/2"}, {"scenes", o.scenes}, {"seed", o.seed},
                              {"question", "Look at the tip of the magenta arrow. Can you see an object there clearly "
                                           "enough to say what it is? If so, name it in one or two words."},
                              {"cases", shown}};
  write_file_atomically(key.string(), [&](std::ostream& os) {
    os << nlohmann::json({{"format", "mtg-sights-key/1"}, {"cases", cases}}).dump(1) << "\n";
  });
  write_file_atomically((out / "sights.json").string(), [&](std::ostream& os) { os << doc.dump(1) << "\n"; });
  std::printf("drew %zu of %zu objects into %s (images/, sights.json: ids and images only); answers go to "
              "%s/labels/<rater>.json as {\"rater\", \"labels\": [{\"id\", \"seen\", \"name\"}]}; the key is %s, "
              "outside the raters' folder\n",
              drawn.size(), all.size(), o.out.c_str(), o.out.c_str(), key.c_str());
  return 0;
}

int run_sights_report(const SightsReportOptions& o) {
  const fs::path dir(o.dir);
  const nlohmann::json doc = read_json_file((dir / "sights.json").string());
  // Draws before mtg-sights/2 kept the answers in sights.json itself; later ones in their key.
  const bool keyed = doc.value("format", std::string()) != "mtg-sights/1";
  const fs::path key = key_path(o.key, dir);
  const nlohmann::json key_doc = keyed ? read_json_file(key.string()) : doc;
  std::vector<render::SightCase> cases;
  std::map<std::string, std::size_t> index;
  for (const nlohmann::json& j : key_doc.at("cases")) {
    cases.push_back(render::sight_case_from_json(j));
    index[cases.back().id] = cases.size() - 1;
  }
  // rater -> case index -> answer
  std::map<std::string, std::map<std::size_t, render::SightAnswer>> by_rater;
  if (fs::is_directory(dir / "labels")) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir / "labels")) {
      if (e.path().extension() == ".json") files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
      const nlohmann::json labels = read_json_file(f.string());
      const std::string rater = labels.value("rater", f.stem().string());
      for (const nlohmann::json& l : labels.at("labels")) {
        render::SightAnswer a = render::sight_answer_from_json(l);
        a.rater = rater;
        const auto it = index.find(a.id);
        if (it == index.end()) throw Error(f.string() + ": no case '" + a.id + "' in sights.json");
        by_rater[rater][it->second] = a;
      }
    }
  }
  if (by_rater.empty()) throw Error("mtg audit sights report: " + o.dir + "/labels holds no answers");
  const render::VisibilityOptions rule;
  nlohmann::json report = {{"rule", rule.to_json()}, {"raters", nlohmann::json::array()}};
  auto table = [&](const std::string& who, const std::vector<render::SightCase>& cs, const std::vector<bool>& labels) {
    const render::Confusion c = render::confusion(cs, labels, rule);
    const render::VisibilityOptions best = render::best_thresholds(cs, labels, rule);
    const render::Confusion cb = render::confusion(cs, labels, best);
    if (!o.json) {
      std::printf("%-10s %3d labels  rule %d px / %.2f: agree %.1f %% (both seen %d, rule only %d, person only %d, "
                  "neither %d); best grid %d px / %.2f: %.1f %%\n",
                  who.c_str(), c.total(), rule.min_pixels, rule.min_share, 100 * c.agreement(), c.both_seen,
                  c.rule_only, c.person_only, c.neither, best.min_pixels, best.min_share, 100 * cb.agreement());
    }
    return nlohmann::json{{"who", who}, {"labels", c.total()}, {"agreement", c.agreement()},
                          {"both_seen", c.both_seen}, {"rule_only", c.rule_only}, {"person_only", c.person_only},
                          {"neither", c.neither}, {"best", best.to_json()}, {"best_agreement", cb.agreement()}};
  };
  // Per rater, then every answer of every rater together.
  std::vector<render::SightCase> pooled;
  std::vector<bool> pooled_labels;
  for (const auto& [rater, answers] : by_rater) {
    std::vector<render::SightCase> cs;
    std::vector<bool> labels;
    for (const auto& [i, a] : answers) {
      cs.push_back(cases[i]);
      labels.push_back(a.label());
    }
    pooled.insert(pooled.end(), cs.begin(), cs.end());
    pooled_labels.insert(pooled_labels.end(), labels.begin(), labels.end());
    report["raters"].push_back(table(rater, cs, labels));
  }
  report["all"] = table("all", pooled, pooled_labels);
  // Agreement between each pair of raters on the cases both answered.
  report["pairs"] = nlohmann::json::array();
  for (auto a = by_rater.begin(); a != by_rater.end(); ++a) {
    for (auto b = std::next(a); b != by_rater.end(); ++b) {
      std::vector<std::string> x, y;
      for (const auto& [i, answer] : a->second) {
        const auto other = b->second.find(i);
        if (other == b->second.end()) continue;
        x.push_back(answer.label() ? "seen" : "not");
        y.push_back(other->second.label() ? "seen" : "not");
      }
      const Agreement ag = agreement(x, y);
      if (!o.json) {
        std::printf("%s / %s: %d cases, %.1f %% agree, Cohen's kappa %.2f\n", a->first.c_str(), b->first.c_str(),
                    ag.questions, ag.percent, ag.kappa);
      }
      report["pairs"].push_back({{"raters", {a->first, b->first}}, {"cases", ag.questions}, {"percent", ag.percent},
                                 {"kappa", ag.kappa}});
    }
  }
  if (o.json) std::printf("%s\n", report.dump(1).c_str());
  return 0;
}

}  // namespace mtg::cli
