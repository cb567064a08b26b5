#include "orchestrator/cli/render_commands.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <ostream>

#include "bus/channels.h"
#include "bus/recording.h"
#include "core/render/image_renderer.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/stopwatch.h"
#include "mtg/observation_t.hpp"

namespace mtg::cli {

namespace fs = std::filesystem;

namespace {

void write_bytes(const fs::path& file, const std::uint8_t* data, std::size_t size) {
  write_file_atomically(file, [&](std::ostream& os) {
    os.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  });
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
  if (o.view == "platform" && o.platform.empty()) throw Error("mtg render: a platform view needs --platform <name>");
  if ((o.view == "item" || o.view == "focus") && o.item.empty()) {
    throw Error("mtg render: an " + o.view + " view needs --item <object name>");
  }

  render::ViewSpec view{render::parse_view_kind(o.view), o.platform, o.side, o.item, render::MarkKind::kNone};
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

  render::ImageRenderer renderer(o.profile);
  const Stopwatch load;
  renderer.scene_renderer(renderer.scenes().load(o.scene, o.data_dir));
  const double load_ms = load.elapsed_ms();
  const Stopwatch draw;
  const render::ImageReply reply = renderer.render(request);
  const double draw_ms = draw.elapsed_ms();
  for (const render::EncodedImage& image : reply.images) {
    const bool marked = image.role.ends_with("_marked");
    const fs::path file = marked ? out.parent_path() / (out.stem().string() + "_marked" + ext) : out;
    write_bytes(file, image.bytes.data(), image.bytes.size());
    std::printf("wrote %s (%dx%d, %s)\n", file.c_str(), image.width, image.height, image.role.c_str());
  }
  std::printf("%lld triangles; scene load %.0f ms, view %.1f ms (%s)\n", static_cast<long long>(reply.triangles),
              load_ms, draw_ms, renderer.gl_description().c_str());
  return 0;
}

int run_images(const ImagesOptions& o) {
  if (o.out.empty()) throw Error("mtg images: --out <folder> is required");
  fs::create_directories(o.out);
  long written = 0;
  bool seen_episode = false;
  bus::for_each_recorded_event(o.run, [&](const lcm::LogEvent& ev) {
    if (!bus::is_episode_channel(ev.channel, bus::EpisodeStream::kObservation)) return;
    mtg::observation_t obs{};
    if (obs.decode(ev.data, 0, ev.datalen) < 0) {
      throw Error("mtg images: a message on " + ev.channel + " in " + o.run + " does not decode");
    }
    if (o.episode >= 0 && obs.header.episode_id != o.episode) return;
    seen_episode = true;
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
      write_bytes(file, img.data.data(), img.data.size());
      ++written;
    }
  });
  if (o.episode >= 0 && !seen_episode) {
    throw Error("episode " + std::to_string(o.episode) + " is not in the recording of " + o.run);
  }
  std::printf("wrote %ld image(s) to %s\n", written, o.out.c_str());
  return 0;
}

}  // namespace mtg::cli
