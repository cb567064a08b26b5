#include "core/graph/object_geometry.h"

namespace mtg::graph {
namespace {

void add_mesh(const scene::Mesh& mesh, const Eigen::Affine3d& T_WA, geom::TriangleSoup& soup) {
  std::vector<Eigen::Vector3d> world(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    world[i] = T_WA * mesh.positions[i].cast<double>();
  }
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    soup.add({world[mesh.indices[t]], world[mesh.indices[t + 1]], world[mesh.indices[t + 2]]});
  }
}

void add_box(const scene::CollisionBox& box, const Eigen::Isometry3d& X_WO, geom::TriangleSoup& soup) {
  Eigen::Vector3d c[8];
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d local((i & 1 ? 0.5 : -0.5) * box.size.x(), (i & 2 ? 0.5 : -0.5) * box.size.y(),
                                (i & 4 ? 0.5 : -0.5) * box.size.z());
    c[i] = X_WO * (box.X_OB * local);
  }
  static constexpr int kQuads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : kQuads) {
    soup.add({c[q[0]], c[q[1]], c[q[2]]});
    soup.add({c[q[0]], c[q[2]], c[q[3]]});
  }
}

}  // namespace

ObjectGeometry object_geometry(const scene::ObjectInstance& object) {
  ObjectGeometry g;
  for (const scene::Part& part : object.parts) {
    if (part.movable_link) continue;
    if (part.render) {
      add_mesh(*part.render, object.X_WO * part.T_OA, g.soup);
    } else if (part.collision) {
      add_mesh(*part.collision, object.X_WO * part.T_OC, g.soup);
    } else {
      for (const auto& box : part.collision_boxes) add_box(box, object.X_WO, g.soup);
    }
  }
  if (g.soup.empty()) return g;
  g.bottom = g.soup.bounds.min().z();
  g.top = g.soup.bounds.max().z();
  std::vector<geom::Point2> xy;
  xy.reserve(g.soup.triangles.size() * 3);
  for (const auto& t : g.soup.triangles) {
    xy.emplace_back(t.a.head<2>());
    xy.emplace_back(t.b.head<2>());
    xy.emplace_back(t.c.head<2>());
  }
  g.footprint = geom::convex_hull(std::move(xy));
  return g;
}

void translate(ObjectGeometry& g, const Eigen::Vector3d& t) {
  geom::TriangleSoup moved;
  for (const auto& tri : g.soup.triangles) moved.add({tri.a + t, tri.b + t, tri.c + t});
  g.soup = std::move(moved);
  g.bottom += t.z();
  g.top += t.z();
  for (auto& p : g.footprint) p += t.head<2>();
}

}  // namespace mtg::graph
