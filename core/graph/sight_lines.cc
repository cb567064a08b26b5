#include "core/graph/sight_lines.h"

#include <array>

namespace mtg::graph {
namespace {

bool line_clear(const Eigen::Vector3d& eye, const Eigen::Vector3d& point, const std::vector<Occluder>& occluders,
                ObjectId except) {
  const Eigen::Vector3d dir = point - eye;
  for (const Occluder& o : occluders) {
    if (o.object == except || o.soup == nullptr) continue;
    if (geom::ray_blocked(*o.soup, eye, dir, 1e-6, 1.0)) return false;
  }
  return true;
}

}  // namespace

Seen count_seen(const Eigen::Vector3d& eye, const std::vector<SightTarget>& targets,
                const std::vector<Occluder>& occluders) {
  Seen seen;
  for (const SightTarget& t : targets) {
    if (t.box.isEmpty()) continue;
    const Eigen::Vector3d c = t.box.center();
    const Eigen::Vector3d half = t.box.sizes() / 2.0;
    // Inset from the box's faces: a point on a face is often just outside the object.
    const std::array<Eigen::Vector3d, 6> points = {
        Eigen::Vector3d(c.x(), c.y(), c.z() + 0.6 * half.z()), Eigen::Vector3d(c.x(), c.y(), c.z()),
        Eigen::Vector3d(c.x() + 0.4 * half.x(), c.y(), c.z()), Eigen::Vector3d(c.x() - 0.4 * half.x(), c.y(), c.z()),
        Eigen::Vector3d(c.x(), c.y() + 0.4 * half.y(), c.z()), Eigen::Vector3d(c.x(), c.y() - 0.4 * half.y(), c.z())};
    int clear = 0;
    for (const Eigen::Vector3d& point : points) clear += line_clear(eye, point, occluders, t.object) ? 1 : 0;
    seen.objects += clear >= 4 ? 1 : 0;
    seen.lines += clear;
  }
  return seen;
}

int clear_lines(const Eigen::Vector3d& eye, const std::vector<Eigen::Vector3d>& points,
                const std::vector<Occluder>& occluders) {
  int clear = 0;
  for (const Eigen::Vector3d& point : points) clear += line_clear(eye, point, occluders, ObjectId()) ? 1 : 0;
  return clear;
}

}  // namespace mtg::graph
