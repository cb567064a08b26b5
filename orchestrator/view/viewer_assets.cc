#include "orchestrator/view/viewer_assets.h"

namespace mtg::web {

// Generated from orchestrator/view/page/ (mtg_embed_text, orchestrator/CMakeLists.txt).
extern const char* const kViewerHtml;
extern const char* const kViewerJs;

const std::vector<Asset>& viewer_assets() {
  static const std::vector<Asset> assets = with_shared_assets(
      {{"index.html", "text/html; charset=utf-8", kViewerHtml}, {"viewer.js", "text/javascript", kViewerJs}});
  return assets;
}

}  // namespace mtg::web
