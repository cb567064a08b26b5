#pragma once
// Files of the browser pages compiled into the binaries (the pages work offline: nothing is
// fetched from the network). The play page is served by the human agent; the viewer (`mtg view`)
// serves its own page with the shared files listed here.

#include <string>
#include <string_view>
#include <vector>

namespace mtg::web {

struct Asset {
  std::string path;  // as requested, without the leading '/': "index.html" is the page itself
  std::string mime;
  std::string_view content;
};

/// common.css and observation.js: what the play page and the viewer show alike.
const std::vector<Asset>& shared_assets();
/// A page's own files after the shared ones: what its server serves.
std::vector<Asset> with_shared_assets(std::vector<Asset> page);
/// The play page (index.html, play.js) and the shared files.
const std::vector<Asset>& play_assets();

}  // namespace mtg::web
