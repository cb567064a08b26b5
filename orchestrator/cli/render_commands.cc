#include "orchestrator/cli/render_commands.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <filesystem>
#include <map>
#include <optional>
#include <ostream>

#include "bus/channels.h"
#include "bus/observation_packing.h"
#include "bus/recording.h"
#include "core/episode/goals.h"
#include "core/render/codec_module.h"
#include "core/render/image_renderer.h"
#include "core/render/mark_layout.h"
#include "core/render/view.h"
#include "core/render/visibility.h"
#include "core/tasks/referring.h"
#include "core/tasks/task_db.h"
#include "core/tasks/validate.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/file_bytes.h"
#include "core/util/stopwatch.h"
#include "mtg/observation_t.hpp"

namespace mtg::cli {

namespace fs = std::filesystem;

namespace {

nlohmann::json point(const Eigen::Vector2d& p) { return {std::round(p.x() * 10) / 10, std::round(p.y() * 10) / 10}; }

nlohmann::json layout_json(const std::string& name, const render::Camera& camera, const render::MarkLayout& layout,
                           const graph::SceneGraph& g) {
  nlohmann::json marks = nlohmann::json::array();
  for (const render::PlacedMark& m : layout.placed) {
    marks.push_back({{"key", "o" + std::to_string(m.number)}, {"number", m.number},
                     {"object", g.objects[m.object].name}, {"anchor", point(m.anchor)}, {"disc", point(m.disc)},
                     {"visible", m.visible}, {"on_object", m.on_object()}});
  }
  nlohmann::json crowded = nlohmann::json::array();
  for (const render::ItemMark& m : layout.crowded) crowded.push_back(m.number);
  return {{"picture", name}, {"width", camera.width}, {"height", camera.height}, {"radius", layout.style.radius},
          {"dot_radius", layout.style.dot_radius}, {"marks", marks}, {"crowded", crowded}};
}

// The id pass the renderer laid the marks out on, the visibility of every object it shows, and
// where each mark went (docs/render.md, "Inspecting a view").
void write_inspection(const RenderOptions& o, render::ImageRenderer& renderer, const graph::SceneCache::Entry& entry,
                      const episode::WorldState& state, const render::ImageRequest& request,
                      const render::ViewSpec& spec) {
  const graph::SceneGraph& g = entry.graph;
  const render::SceneGeometry& geometry = renderer.geometry(entry);
  render::ViewRequest r;
  r.view = spec.view;
  r.marks = spec.marks;
  r.width = request.width;
  r.height = request.height;
  r.side = spec.side;
  r.platform = g.find_platform(spec.platform);
  r.object = g.find_object(spec.item);
  const render::ViewPlan plan = render::plan_view(g, state, r);
  const int scale = render::kMarkPassScale;
  const render::Camera pass = render::at_resolution(plan.camera, std::max(1, r.width / scale), std::max(1, r.height / scale));
  const render::IdView ids = render::draw_id_view(g, geometry, state, pass, plan.hidden, plan.only);
  if (!o.ids.empty()) {
    cv::Mat png(ids.image.height, ids.image.width, CV_16UC1);
    for (int v = 0; v < ids.image.height; ++v) {
      for (int u = 0; u < ids.image.width; ++u) png.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(ids.image.at(u, v) + 1);
    }
    std::vector<std::uint8_t> bytes;
    if (!render::encode_with_imgcodecs(".png", png, bytes)) throw Error("mtg render: cannot encode " + o.ids);
    write_file_bytes_atomically(o.ids, bytes);
    std::printf("wrote %s (%dx%d id pass, 16-bit: object index + 1)\n", o.ids.c_str(), png.cols, png.rows);
  }
  if (o.marks_json.empty()) return;
  const render::VisibilityOptions thresholds;
  const double pixel_area = static_cast<double>(scale) * scale;
  nlohmann::json legend = nlohmann::json::array();
  for (const render::ObjectSight& seen : ids.objects) {
    const graph::GraphObject& obj = g.objects[graph::ObjectId::of_index(static_cast<std::size_t>(seen.object))];
    legend.push_back({{"value", seen.object + 1}, {"object", obj.name}, {"noun", tasks::noun_of(obj, tasks::Ambiguity::kNoun)},
                      {"pickable", obj.pickable()}, {"visible_pixels", seen.visible * pixel_area},
                      {"silhouette_pixels", seen.silhouette * pixel_area}, {"share", std::round(seen.share() * 1000) / 1000},
                      {"clearly_visible", seen.visible * pixel_area >= thresholds.min_pixels && seen.share() >= thresholds.min_share}});
  }
  nlohmann::json pictures = nlohmann::json::array();
  nlohmann::json problems = nlohmann::json::array();
  if (!plan.marks.items.empty()) {
    const render::ItemMarksPlan marks = render::plan_item_marks(g, geometry, state, plan.camera, plan.marks.items, plan.hidden);
    pictures.push_back(layout_json("picture", plan.camera, marks.layout, g));
    for (std::size_t k = 0; k < marks.zooms.size(); ++k) {
      nlohmann::json z = layout_json(render::zoom_name(k), marks.zooms[k].view.camera, marks.zooms[k].layout, g);
      z["region"] = {point(marks.zooms[k].view.region.min()), point(marks.zooms[k].view.region.max())};
      pictures.push_back(z);
    }
    for (const std::string& p : marks.problems()) problems.push_back(p);
  }
  const nlohmann::json doc = {{"scene", o.scene}, {"view", o.view}, {"platform", spec.platform}, {"side", plan.side},
                              {"image", {r.width, r.height}}, {"id_pass", {{"width", ids.image.width}, {"height", ids.image.height},
                              {"scale", scale}, {"file", o.ids}}}, {"thresholds", thresholds.to_json()},
                              {"legend", legend}, {"pictures", pictures}, {"problems", problems}};
  write_file_atomically(o.marks_json, [&](std::ostream& os) { os << doc.dump(1) << "\n"; });
  std::printf("wrote %s (%zu objects in view, %zu pictures of marks, %zu problems)\n", o.marks_json.c_str(),
              legend.size(), pictures.size(), problems.size());
}

}  // namespace

int run_render(const RenderOptions& o) {
  if (o.out.empty()) throw Error("mtg render: --out <file.png|file.jpg> is required");
  const fs::path out(o.out);
  const std::string ext = out.extension().string();
  std::string encoding;
  if (ext == ".png") encoding = "png";
  if (ext == ".jpg" || ext == ".jpeg") encoding = "jpeg";
  if (encoding.empty()) throw Error("mtg render: --out must end in .png, .jpg or .jpeg: " + o.out);
  if ((o.view == "item" || o.view == "focus") && o.item.empty()) {
    throw Error("mtg render: an " + o.view + " view needs --item <object name>");
  }

  render::ImageRenderer renderer(o.profile);
  const graph::SceneCache::Entry& entry = renderer.scenes().load(o.scene, o.data_dir);
  // A task's part: its start (or, holding, once its item is picked), at the platform it is about.
  episode::WorldState state = episode::initial_state(entry.graph);
  std::string platform = o.platform;
  if (!o.task.empty()) {
    if (o.tasks.empty()) throw Error("mtg render: --task needs --tasks <task database>");
    const std::vector<tasks::Task> all = tasks::read_tasks(o.tasks);
    const auto it = std::find_if(all.begin(), all.end(), [&](const tasks::Task& t) { return t.id == o.task; });
    if (it == all.end()) throw Error("mtg render: " + o.tasks + " has no task '" + o.task + "'");
    if (it->scene != o.scene) throw Error("mtg render: task " + o.task + " is of scene " + it->scene + ", not " + o.scene);
    state = tasks::start_of_part(entry.graph, *it, tasks::TaskOptions{}, o.part, o.holding);
    if (platform.empty() && o.view == "platform") {
      const episode::TaskGoal goal = episode::task_goal_from_json(entry.graph, it->goal);
      const episode::AtomicGoal& g = goal.parts.at(static_cast<std::size_t>(o.part));
      platform = entry.graph.platforms[o.holding ? g.platform : g.source].name;
    }
  }
  if (o.view == "platform" && platform.empty()) throw Error("mtg render: a platform view needs --platform <name>");

  render::ViewSpec view{render::parse_view_kind(o.view), platform, o.side, o.item, render::MarkKind::kNone, 0, ""};
  if (o.marks == "auto") {
    view.marks = view.view == render::ViewKind::kPlatform  ? render::MarkKind::kItems
                 : view.view == render::ViewKind::kTopdown ? render::MarkKind::kLabels
                                                           : render::MarkKind::kNone;
  } else if (o.marks != "none") {
    view.marks = render::parse_mark_kind(o.marks);
  }
  render::ImageRequest request;
  request.scene = o.scene;
  request.data_dir = o.data_dir;
  request.width = o.width;
  request.height = o.height;
  request.encoding = encoding;
  request.views = {view};
  request.state = episode::state_delta(entry.graph, state);

  const Stopwatch load;
  renderer.scene_renderer(entry);
  const double load_ms = load.elapsed_ms();
  const Stopwatch draw;
  const render::ImageReply reply = renderer.render(request);
  const double draw_ms = draw.elapsed_ms();
  int zooms = 0;
  int pictures = 0;  // a long platform's view has a picture of each part after the whole
  for (const render::EncodedImage& image : reply.images) {
    const bool marked = image.role.ends_with("_marked");
    const bool zoom = image.role.ends_with("_zoom");
    if (!marked && !zoom) ++pictures;
    const std::string stem = out.stem().string() + (pictures > 1 ? "_part" + std::to_string(pictures - 1) : "");
    const fs::path file = zoom     ? out.parent_path() / (out.stem().string() + "_zoom" + std::to_string(++zooms) + ext)
                          : marked ? out.parent_path() / (stem + "_marked" + ext)
                                   : out.parent_path() / (stem + ext);
    write_file_bytes_atomically(file, image.bytes);
    std::printf("wrote %s (%dx%d, %s)\n", file.c_str(), image.width, image.height, image.role.c_str());
  }
  std::printf("%lld triangles; scene load %.0f ms, view %.1f ms (%s)\n", static_cast<long long>(reply.triangles),
              load_ms, draw_ms, renderer.gl_description().c_str());
  if (!o.ids.empty() || !o.marks_json.empty()) write_inspection(o, renderer, entry, state, request, view);
  return 0;
}

int run_images(const ImagesOptions& o) {
  if (o.out.empty()) throw Error("mtg images: --out <folder> is required");
  fs::create_directories(o.out);
  long written = 0, unreadable = 0;
  bool seen_episode = false;
  // Observations come packed (bus/observation_packing.h): each attempt's are made whole in the
  // order recorded; an unchanged view is written at every step that showed it, as the agent saw it.
  bus::RecordedObservations observations;
  const auto damage = bus::for_each_recorded_event(o.run, [&](const lcm::LogEvent& ev) {
    if (!bus::is_episode_channel(ev.channel, bus::EpisodeStream::kObservation)) return;
    mtg::observation_t packed{};
    if (packed.decode(ev.data, 0, ev.datalen) < 0) {
      throw Error("mtg images: a message on " + ev.channel + " in " + o.run + " does not decode");
    }
    if (o.episode >= 0 && packed.header.episode_id != o.episode) return;
    seen_episode = true;
    std::optional<mtg::observation_t> whole;
    try {
      whole = observations.whole(packed);
    } catch (const Error& e) {
      std::fprintf(stderr, "mtg images: %s; not written\n", e.what());
      ++unreadable;
      return;
    }
    if (!whole) return;  // a second copy of an attempt's last observation
    const mtg::observation_t& obs = *whole;
    // An observation may hold several images of one role (a close-up per look-alike): the
    // second and later get _2, _3, ... so that none overwrites another.
    std::map<std::string, int> of_role;
    for (const mtg::image_t& img : obs.images) {
      if (img.nbytes == 0) continue;
      const std::string ext = img.encoding == "jpeg" ? ".jpg" : ".png";
      const int n = ++of_role[img.role];
      const std::string name = "e" + std::to_string(obs.header.episode_id) + "_a" + std::to_string(obs.header.attempt) +
                               "_s" + std::to_string(obs.step) + "_" + img.role +
                               (n > 1 ? "_" + std::to_string(n) : std::string()) + ext;
      const fs::path file = fs::path(o.out) / name;
      write_file_bytes_atomically(file, img.data);
      ++written;
    }
  });
  for (const bus::RecordingDamage& d : damage) std::fprintf(stderr, "mtg images: %s\n", bus::describe(d).c_str());
  const std::string damaged = damage.empty() ? "" : " (the recording is damaged: " + bus::describe(damage.front()) + ")";
  if (o.episode >= 0 && !seen_episode) {
    const std::string why = bus::damage_for(damage, bus::EpisodeId(o.episode));
    throw Error("episode " + std::to_string(o.episode) + " is not in the recording of " + o.run +
                (why.empty() ? "" : " (the recording is damaged: " + why + ")"));
  }
  if (written == 0 && !damage.empty()) {
    throw Error("no image read from " + o.run + ", and the recording is damaged: images may have been in what "
                "could not be read" + damaged);
  }
  std::printf("wrote %ld image(s) to %s%s\n", written, o.out.c_str(),
              unreadable > 0 ? (" (" + std::to_string(unreadable) + " observation(s) refer to what the recording lacks)").c_str()
                             : "");
  return 0;
}

}  // namespace mtg::cli
