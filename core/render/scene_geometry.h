#pragma once
// The scene's triangles without GL: what the renderer draws of each graph object (render meshes,
// the collision mesh where the render mesh is missing, doors and drawers left out), as positions
// in the object's frame. The CPU id pass (id_raster.h) draws them, so task generation, the
// renderer's marks and an independent checker all see the same pixels, bit for bit on any machine.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/graph/scene_graph.h"
#include "core/scene/scene.h"
#include "core/util/id_vector.h"

namespace mtg::render {

/// One graph object's triangles in its own frame O (the frame GraphObject::X_WO places).
struct ObjectTriangles {
  std::vector<Eigen::Vector3f> vertices_O;
  std::vector<std::uint32_t> indices;  // 3 per triangle
  Eigen::AlignedBox3f box_O;           // of vertices_O; empty when there are none

  std::size_t triangle_count() const { return indices.size() / 3; }
};

class SceneGeometry {
 public:
  SceneGeometry() = default;
  /// Graph objects are matched to scene objects by name, as SceneRenderer does.
  SceneGeometry(const scene::Scene& scene, const graph::SceneGraph& g);

  const ObjectTriangles& of(graph::ObjectId o) const { return objects_.at(o); }
  std::size_t size() const { return objects_.size(); }
  std::size_t triangle_count() const;

 private:
  IdVector<graph::ObjectId, ObjectTriangles> objects_;
};

}  // namespace mtg::render
