#include "core/scene/scene_summary.h"

#include <map>

namespace mtg::scene {

nlohmann::json summarize_scene(const Scene& scene) {
  int articulated = 0;
  int receptacles = 0;
  std::size_t triangles = 0;
  std::map<std::string, int> by_motion;
  Eigen::AlignedBox3d bounds;
  for (const ObjectInstance& o : scene.objects) {
    articulated += o.articulated ? 1 : 0;
    receptacles += static_cast<int>(o.receptacles.size());
    triangles += o.render_triangles();
    by_motion[to_string(o.motion)] += 1;
    const auto b = o.world_bounds();
    if (!b.isEmpty()) bounds.extend(b);
  }
  nlohmann::json j;
  j["scene"] = scene.name;
  j["objects"] = scene.objects.size();
  j["rigid"] = static_cast<int>(scene.objects.size()) - articulated;
  j["articulated"] = articulated;
  j["by_motion_type"] = by_motion;
  j["receptacles"] = receptacles;
  j["meshes_loaded"] = scene.stats.meshes_loaded;
  j["meshes_missing"] = scene.stats.meshes_missing;
  j["triangles"] = triangles;
  if (!bounds.isEmpty()) {
    j["bounds"] = {{"min", {bounds.min().x(), bounds.min().y(), bounds.min().z()}},
                   {"max", {bounds.max().x(), bounds.max().y(), bounds.max().z()}}};
  }
  j["stage_mesh_present"] = scene.stage_mesh_present;
  j["load_ms"] = scene.stats.load_ms;
  j["warnings"] = scene.warnings;
  return j;
}

}  // namespace mtg::scene
