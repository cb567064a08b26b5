#include "core/scene/scene.h"

namespace mtg::scene {

const char* to_string(MotionType type) {
  switch (type) {
    case MotionType::kStatic: return "STATIC";
    case MotionType::kDynamic: return "DYNAMIC";
    case MotionType::kKinematic: return "KINEMATIC";
  }
  return "?";
}

Eigen::Matrix3d yup_to_zup() {
  Eigen::Matrix3d c;
  c << 1, 0, 0,  //
      0, 0, -1,  //
      0, 1, 0;
  return c;
}

Eigen::AlignedBox3d ObjectInstance::world_bounds() const {
  Eigen::AlignedBox3d box;
  for (const Part& part : parts) {
    const Mesh* mesh = part.render ? part.render.get() : part.collision.get();
    const Eigen::Affine3d T_WA = X_WO * (part.render ? part.T_OA : part.T_OC);
    if (mesh != nullptr) {
      for (const auto& p : mesh->positions) box.extend(T_WA * p.cast<double>());
    }
    for (const CollisionBox& b : part.collision_boxes) {
      if (mesh != nullptr) break;  // boxes only stand in when there is no mesh at all
      for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3d local((corner & 1 ? 0.5 : -0.5) * b.size.x(),
                                    (corner & 2 ? 0.5 : -0.5) * b.size.y(),
                                    (corner & 4 ? 0.5 : -0.5) * b.size.z());
        box.extend(X_WO * (b.X_OB * local));
      }
    }
  }
  return box;
}

std::size_t ObjectInstance::render_triangles() const {
  std::size_t n = 0;
  for (const Part& part : parts) {
    if (part.render) n += part.render->triangle_count();
  }
  return n;
}

const ObjectInstance* Scene::find(const std::string& object_name) const {
  for (const auto& o : objects) {
    if (o.name == object_name) return &o;
  }
  return nullptr;
}

}  // namespace mtg::scene
