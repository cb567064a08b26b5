#include "core/render/render_pool.h"

#include <algorithm>
#include <string>

#include "core/util/error.h"

namespace mtg::render {

int default_renderers(int cores, int gpus) {
  // Each renderer holds the scenes with their textures (~0.5 GB for an apartment): past eight
  // (or one per GPU) the memory grows faster than what more renderers add; --renderers goes further.
  return std::max(1, std::min(std::max(cores / 4, gpus), std::max(kMaxDefaultRenderers, gpus)));
}

std::vector<RendererSlot> plan_render_pool(int renderers, int cores, int gpus) {
  if (renderers < 0) throw Error("--renderers must be 0 (one per four cores) or more, not " + std::to_string(renderers));
  cores = std::max(1, cores);
  gpus = std::max(0, gpus);
  const int n = renderers == 0 ? default_renderers(cores, gpus) : renderers;
  std::vector<RendererSlot> pool;
  for (int k = 0; k < n; ++k) {
    RendererSlot s;
    s.index = k;
    // The cores split as evenly as they go: the first (cores mod n) renderers get one more.
    const int share = std::max(1, cores / n + (k < cores % n ? 1 : 0));
    s.gpu = gpus > 0 ? k % gpus : -1;
    s.draw_threads = gpus > 0 ? 0 : share;
    s.encode_threads = share;
    pool.push_back(s);
  }
  return pool;
}

int least_loaded(const std::vector<int>& load) {
  if (load.empty()) return 0;
  return static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
}

}  // namespace mtg::render
