// `mtg bench render`: the renderer's figures (issue 7) on llvmpipe or a GPU: scene upload, ms per
// annotated observation at two sizes over every navigable platform of a scene, triangles per
// frame, memory, and whole oracle episodes with the images the scene-graph service would ask for.
// Wall-clock here is telemetry only.

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <vector>

#include "core/episode/goals.h"
#include "core/episode/rules.h"
#include "core/render/image_codec.h"
#include "core/render/image_renderer.h"
#include "core/render/overlay.h"
#include "core/render/view.h"
#include "core/tasks/generator.h"
#include "core/util/parallel.h"
#include "core/util/stopwatch.h"
#include "orchestrator/cli/bench_commands.h"

namespace mtg::cli {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

// Images encoded as the renderer encodes a reply's: all at once, one thread per core.
std::size_t encoded_bytes(const std::vector<const cv::Mat*>& images) {
  std::size_t bytes = 0;
  for (const auto& b : render::encode_images(images, "png", default_jobs())) bytes += b.size();
  return bytes;
}

// Renders, marks and encodes every view an observation in `s` asks for, as the renderer does
// (every view drawn, then all images encoded together); returns the bytes.
std::size_t observation_images(render::SceneRenderer& renderer, const render::SceneGeometry& geometry,
                               const graph::SceneGraph& g, const episode::WorldState& s, int width, int height,
                               double min_region, std::int64_t& triangles) {
  std::vector<render::ViewImages> drawn;
  for (const render::ViewRequest& v : render::observation_views(s, width, height, min_region)) {
    const render::ViewPlan plan = render::plan_view(g, s, v);
    drawn.push_back(render::draw_view(renderer, g, s, plan, v.marks != render::MarkKind::kNone, geometry));
    triangles += drawn.back().triangles;
  }
  return encoded_bytes(render::images_in_reply_order(drawn));
}

}  // namespace

int run_bench_render(const BenchRenderOptions& o) {
  render::ImageRenderer renderer(o.profile);
  std::printf("renderer: %s; images encoded on up to %d threads\n", renderer.gl_description().c_str(), default_jobs());
  Stopwatch load;
  const graph::SceneCache::Entry& entry = renderer.scenes().load(o.scene, o.data_dir);
  const double scene_ms = load.elapsed_ms();
  load.reset();
  render::SceneRenderer& gpu = renderer.scene_renderer(entry);
  const double upload_ms = load.elapsed_ms();
  const graph::SceneGraph& g = entry.graph;
  const render::SceneGeometry& geometry = renderer.geometry(entry);
  std::printf("%s: scene + graph %.0f ms, GPU upload (meshes, textures <= %d px) %.0f ms, textures %.0f MiB\n",
              o.scene.c_str(), scene_ms, render::RendererOptions{}.max_texture_size, upload_ms,
              static_cast<double>(gpu.uploaded_texture_bytes()) / (1 << 20));

  const episode::WorldState initial = episode::initial_state(g);
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{640, 480}, {1280, 720}}) {
    std::vector<double> frame_ms, observation_ms, plan_ms, draw_ms, marks_ms;
    std::int64_t triangles = 0;
    std::size_t bytes = 0;
    int frames = 0, zooms = 0;
    const auto view_of = [&, w = w, h = h](graph::PlatformId p) {
      render::ViewRequest r;
      r.platform = p;
      r.width = w;
      r.height = h;
      r.marks = render::MarkKind::kItems;
      return r;
    };
    // One untimed pass first: a GPU raises its clocks only after some work, and the first draw
    // at a size allocates the framebuffer.
    for (const graph::PlatformId p : g.navigable) {
      render::draw_view(gpu, g, initial, render::plan_view(g, initial, view_of(p)), true, geometry);
    }
    for (int round = 0; round < o.rounds; ++round) {
      for (const graph::PlatformId p : g.navigable) {
        const render::ViewRequest r = view_of(p);
        // The phases of draw_view(..., true), timed apart: planning is CPU work; the draw is the
        // GL draw and read-back (timed alone on a second draw of the same view); the marks are
        // the rest: the CPU id pass, the layout, drawing them, and any zoomed view's GL draw.
        Stopwatch watch;
        const render::ViewPlan plan = render::plan_view(g, initial, r);
        const double planned = watch.elapsed_ms();
        const std::vector<render::ViewImages> drawn_views{render::draw_view(gpu, g, initial, plan, true, geometry)};
        const render::ViewImages& images = drawn_views.front();
        frame_ms.push_back(watch.elapsed_ms());
        bytes += encoded_bytes(render::images_in_reply_order(drawn_views));
        observation_ms.push_back(watch.elapsed_ms());
        Stopwatch draw_only;
        (void)render::draw_view(gpu, g, initial, plan, false, geometry);
        const double drawn = draw_only.elapsed_ms();
        plan_ms.push_back(planned);
        draw_ms.push_back(drawn);
        marks_ms.push_back(frame_ms.back() - planned - drawn);
        zooms += static_cast<int>(images.zooms.size());
        triangles += images.triangles;
        ++frames;
      }
    }
    std::printf("%dx%d platform views (%d, every navigable platform x %d, after one untimed pass): annotated frame median %.1f ms, "
                "mean %.1f ms = %.0f frames/s; with both PNGs encoded median %.1f ms = %.0f observations/s; "
                "%lld triangles/frame; %.0f KiB PNG per observation (plain + marked)\n",
                w, h, frames, o.rounds, median(frame_ms), mean(frame_ms), 1000.0 / mean(frame_ms),
                median(observation_ms), 1000.0 / mean(observation_ms), static_cast<long long>(triangles / frames),
                static_cast<double>(bytes) / frames / 1024.0);
    std::printf("  zoomed views %d (%.2f per view); of a frame (medians): plan %.2f ms, draw + read back %.2f ms, marks %.2f ms\n",
                zooms, static_cast<double>(zooms) / frames, median(plan_ms),
                median(draw_ms), median(marks_ms));
  }

  // Whole oracle episodes, rendered as the service would: every observation's views at 640x480.
  tasks::TaskOptions task_options;
  task_options.levels = {1, 2};
  const auto generated = tasks::generate_tasks(entry.scene, g, task_options);
  std::vector<double> episode_ms;
  std::vector<double> steps;
  const episode::RuleOptions rules;
  for (std::size_t i = 0; i < generated.set.tasks.size() && static_cast<int>(episode_ms.size()) < o.episodes;
       i += std::max<std::size_t>(1, generated.set.tasks.size() / static_cast<std::size_t>(o.episodes))) {
    const tasks::Task& task = generated.set.tasks[i];
    episode::TaskConstraints constraints;
    constraints.protected_objects = episode::task_goal_from_json(g, task.goal).protected_objects();
    episode::WorldState s = episode::initial_state(g);
    std::int64_t triangles = 0;
    Stopwatch watch;
    observation_images(gpu, geometry, g, s, 640, 480, rules.min_region_size, triangles);
    for (const std::string& key : task.oracle) {
      episode::apply_action(g, s, key, constraints, rules);
      observation_images(gpu, geometry, g, s, 640, 480, rules.min_region_size, triangles);
    }
    episode_ms.push_back(watch.elapsed_ms());
    steps.push_back(static_cast<double>(task.oracle.size()));
  }
  std::printf("oracle episodes with images (640x480, %zu Level 1-2 tasks, %.1f steps on average): median %.0f ms, "
              "max %.0f ms per episode = %.1f episodes/s in one process\n",
              episode_ms.size(), mean(steps), median(episode_ms),
              episode_ms.empty() ? 0.0 : *std::max_element(episode_ms.begin(), episode_ms.end()),
              episode_ms.empty() ? 0.0 : 1000.0 / mean(episode_ms));
  std::printf("peak RSS %.0f MiB\n", peak_rss_mib());
  return 0;
}

}  // namespace mtg::cli
