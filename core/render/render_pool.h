#pragma once
// How many renderer processes a host runs and what each of them uses (docs/render.md, "A pool
// of renderers"). Pure arithmetic of the cores and GPUs present; the local runtime starts the
// processes and the scene-graph service spreads episodes over them.
//
// Why several processes: one renderer draws one request at a time on its GL context, and an
// observation's PNGs are most of its time; a process per share of the cores draws and encodes
// several episodes' observations at once, and a renderer that dies takes only its own share.

#include <vector>

namespace mtg::render {

/// What one renderer of the pool is told.
struct RendererSlot {
  int index = 0;           // its place in the pool (its request channel, bus::render_request_channel)
  int gpu = -1;            // the hardware EGL device it draws on (-1: none present; llvmpipe)
  int draw_threads = 0;    // llvmpipe's rasteriser threads (LP_NUM_THREADS); 0 on a GPU
  int encode_threads = 1;  // threads encoding its images
};

/// The pool's size when the user does not give one: a renderer per four cores (drawing one
/// request while its encoders write the last one's PNGs keeps about that many busy), at least
/// one per GPU, at least one, and no more than kMaxDefaultRenderers or the GPUs.
int default_renderers(int cores, int gpus);
inline constexpr int kMaxDefaultRenderers = 8;

/// The pool of `renderers` processes (0 = default_renderers) on `cores` cores and `gpus`
/// hardware GPUs: renderers go round the GPUs; each gets an equal share of the cores for
/// encoding and, without a GPU, for llvmpipe (so N renderers never run more threads than
/// cores, and a comparison of pool sizes is fair). @throws mtg::Error for a negative size.
std::vector<RendererSlot> plan_render_pool(int renderers, int cores, int gpus);

/// The renderer for a new episode: the one holding the fewest episodes now (the first of those
/// on a tie). `load[k]` is what renderer k holds. An episode keeps its renderer to the end, so
/// its images referring to earlier ones (bus/observation_packing.h) stay with one process.
int least_loaded(const std::vector<int>& load);

}  // namespace mtg::render
