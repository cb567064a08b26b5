#include "core/graph/overlap_check.h"

#include <fcl/fcl.h>

#include <map>
#include <memory>

namespace mtg::graph {
namespace {

using Model = fcl::BVHModel<fcl::OBBRSSd>;

std::shared_ptr<Model> build_model(const geom::TriangleSoup& soup, double tolerance) {
  auto model = std::make_shared<Model>();
  const Eigen::Vector3d centre = soup.bounds.center();
  const Eigen::Vector3d half = soup.bounds.sizes() / 2.0;
  // Per-axis shrink so every face moves inwards by about `tolerance`.
  Eigen::Vector3d factor;
  for (int k = 0; k < 3; ++k) factor[k] = half[k] > 2.0 * tolerance ? 1.0 - tolerance / half[k] : 0.5;
  model->beginModel();
  for (const auto& t : soup.triangles) {
    auto shrink = [&](const Eigen::Vector3d& p) -> fcl::Vector3d {
      return centre + (p - centre).cwiseProduct(factor);
    };
    model->addTriangle(shrink(t.a), shrink(t.b), shrink(t.c));
  }
  model->endModel();
  return model;
}

}  // namespace

std::vector<std::pair<int, int>> interpenetrating_pairs(
    const std::vector<const geom::TriangleSoup*>& meshes,
    const std::vector<std::pair<int, int>>& candidates, double tolerance) {
  std::map<int, std::shared_ptr<Model>> models;
  auto model_of = [&](int i) {
    auto it = models.find(i);
    if (it == models.end()) it = models.emplace(i, build_model(*meshes.at(static_cast<size_t>(i)), tolerance)).first;
    return it->second;
  };
  std::vector<std::pair<int, int>> out;
  for (const auto& [a, b] : candidates) {
    if (meshes.at(static_cast<size_t>(a))->empty() || meshes.at(static_cast<size_t>(b))->empty()) continue;
    fcl::CollisionObjectd oa(model_of(a)), ob(model_of(b));
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    fcl::collide(&oa, &ob, request, result);
    if (result.isCollision()) out.emplace_back(std::min(a, b), std::max(a, b));
  }
  return out;
}

}  // namespace mtg::graph
