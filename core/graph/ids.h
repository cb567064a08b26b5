#pragma once
// Ids of the scene graph's objects and platforms: positions in SceneGraph::objects and
// SceneGraph::platforms, typed so that one cannot be passed for the other. None is the default.
// They never leave the process: the graph JSON, the task database and the bus name objects and
// platforms, since every host builds its own graph.

#include "core/util/typed_id.h"

namespace mtg::graph {

using ObjectId = TypedId<struct ObjectTag>;
using PlatformId = TypedId<struct PlatformTag>;

}  // namespace mtg::graph
