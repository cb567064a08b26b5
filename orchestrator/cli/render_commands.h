#pragma once
// `mtg render`: one view of a scene as the agent would see it, written to image files
// (docs/render.md). It renders in this process, with the renderer service's code.
// `mtg images`: the images of a recorded run, as files.

#include <string>

namespace mtg::cli {

struct RenderOptions {
  std::string scene;
  std::string data_dir;
  std::string profile = "replica_cad";
  std::string view = "platform";  // platform, item, topdown
  std::string platform;
  int side = -1;
  std::string item;
  std::string marks = "auto";     // auto: items for platforms, labels for the overview, none for items
  int width = 640;
  int height = 480;
  std::string out;                // plain image; the marked copy goes beside it as <stem>_marked<ext>
  // Inspection (docs/render.md, "Inspecting a view"): the id pass and the marks, for checkers.
  std::string ids;                // 16-bit PNG of the id pass (object index + 1; 0 nothing)
  std::string marks_json;         // the legend, every object's pixels and each mark's place
  // The state to draw: a task's start of one part (its oracle plan played up to there).
  std::string tasks;
  std::string task;
  int part = 0;
  bool holding = false;           // once the part's item is picked (its destination's view)
};

int run_render(const RenderOptions& options);

/// `mtg images RUN --out DIR [--episode N]`: the images the agents saw, from a run's recording.
struct ImagesOptions {
  std::string run;
  std::string out;
  long long episode = -1;  // -1 = every episode
};

int run_images(const ImagesOptions& options);

}  // namespace mtg::cli
