#include "agents/human/web_assets.h"

namespace mtg::web {

// Generated from agents/human/page/ (mtg_embed_text, agents/CMakeLists.txt).
extern const char* const kCommonCss;
extern const char* const kObservationJs;
extern const char* const kPlayHtml;
extern const char* const kPlayJs;

const std::vector<Asset>& shared_assets() {
  static const std::vector<Asset> assets = {{"common.css", "text/css", kCommonCss},
                                            {"observation.js", "text/javascript", kObservationJs}};
  return assets;
}

const std::vector<Asset>& play_assets() {
  static const std::vector<Asset> assets = [] {
    std::vector<Asset> a = shared_assets();
    a.push_back({"index.html", "text/html; charset=utf-8", kPlayHtml});
    a.push_back({"play.js", "text/javascript", kPlayJs});
    return a;
  }();
  return assets;
}

}  // namespace mtg::web
