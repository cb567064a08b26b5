#include "agents/human/web_assets.h"

namespace mtg::web {

// Generated from orchestrator/audit/page/ (mtg_embed_text, orchestrator/CMakeLists.txt).
extern const char* const kAuditHtml;
extern const char* const kAuditJs;

const std::vector<Asset>& audit_assets() {
  static const std::vector<Asset> assets = with_shared_assets(
      {{"index.html", "text/html; charset=utf-8", kAuditHtml}, {"audit.js", "text/javascript", kAuditJs}});
  return assets;
}

}  // namespace mtg::web
