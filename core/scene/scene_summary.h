#pragma once
// The numbers `mtg scene info` prints about a loaded scene.

#include <nlohmann/json.hpp>

#include "core/scene/scene.h"

namespace mtg::scene {

/// Counts, bounds and load time of a scene: keys scene, objects, rigid, articulated,
/// by_motion_type, receptacles, meshes_loaded, meshes_missing, triangles, bounds, load_ms,
/// stage_mesh_present, warnings.
nlohmann::json summarize_scene(const Scene& scene);

}  // namespace mtg::scene
