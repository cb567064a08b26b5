#include "core/render/scene_geometry.h"

namespace mtg::render {

SceneGeometry::SceneGeometry(const scene::Scene& scene, const graph::SceneGraph& g) : objects_(g.objects.size()) {
  for (const graph::ObjectId i : g.objects.ids()) {
    const scene::ObjectInstance* inst = scene.find(g.objects[i].name);
    if (inst == nullptr) continue;
    ObjectTriangles& out = objects_[i];
    for (const scene::Part& part : inst->parts) {
      if (part.movable_link) continue;  // doors and drawers: the renderer leaves them out too
      const scene::MeshHandle& mesh = part.render ? part.render : part.collision;
      if (!mesh) continue;
      const Eigen::Affine3f T = (part.render ? part.T_OA : part.T_OC).cast<float>();
      const auto first = static_cast<std::uint32_t>(out.vertices_O.size());
      for (const Eigen::Vector3f& p : mesh->positions) {
        out.vertices_O.push_back(T * p);
        out.box_O.extend(out.vertices_O.back());
      }
      for (const std::uint32_t k : mesh->indices) out.indices.push_back(first + k);
    }
  }
}

std::size_t SceneGeometry::triangle_count() const {
  std::size_t n = 0;
  for (const ObjectTriangles& o : objects_) n += o.triangle_count();
  return n;
}

}  // namespace mtg::render
