#include "agents/human/web_assets.h"

#include <utility>

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

std::vector<Asset> with_shared_assets(std::vector<Asset> page) {
  std::vector<Asset> all = shared_assets();
  for (Asset& a : page) all.push_back(std::move(a));
  return all;
}

const std::vector<Asset>& play_assets() {
  static const std::vector<Asset> assets = with_shared_assets(
      {{"index.html", "text/html; charset=utf-8", kPlayHtml}, {"play.js", "text/javascript", kPlayJs}});
  return assets;
}

}  // namespace mtg::web
