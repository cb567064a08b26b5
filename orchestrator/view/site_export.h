#pragma once
// `mtg export`: a static, self-contained copy of what `mtg view` shows for some runs (overview,
// Sankeys per agent, episode list with search and sort, every episode page with its requests,
// images and goal), to send to a colleague or publish. It opens from file:// and works offline:
// the viewer's own page reads data files (data/...js, each a mtgPut call, because browsers do not
// fetch file:// URLs) through page/static_api.js instead of the server. Images are written once
// per content (img/<sha256>.<ext>): a view that did not change between steps or episodes is one
// file. docs/view.md "Sharing a run".

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace mtg::orchestrator::view {

struct ExportStats {
  std::size_t runs = 0;
  std::size_t episodes = 0;
  std::size_t attempts = 0;      // episode pages (one per recorded attempt)
  std::size_t images = 0;        // image files written (after sharing identical ones)
  std::size_t image_refs = 0;    // images the pages show
  std::uintmax_t bytes = 0;      // everything written
  std::size_t truths_missing = 0;  // attempts whose goal could not be read (no truth.key)
  std::vector<std::string> damage;  // per run, what the viewer names as damaged or missing
};

/// Exports `runs` into `out`, which must not exist or be empty. `progress(done, total)` is
/// called after each episode. Same runs, same bytes. @throws mtg::Error naming the folder or
/// file at fault.
ExportStats export_site(const std::vector<std::filesystem::path>& runs, const std::filesystem::path& out,
                        const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace mtg::orchestrator::view
