#pragma once
// The viewer's page files, compiled into `mtg` (orchestrator/view/page/), with the files it shares
// with the play page.

#include <vector>

#include "agents/human/web_assets.h"

namespace mtg::web {

/// index.html, viewer.js and shared_assets().
const std::vector<Asset>& viewer_assets();

}  // namespace mtg::web
