#include "core/graph/surfaces.h"

#include <algorithm>
#include <cmath>

namespace mtg::graph {
namespace {

struct Face {
  double z;      // centroid height
  double area;   // projected area
  geom::Ring xy;
};

// Closing (grow then shrink) by this much joins faces that only touch at slightly
// mismatched vertices.
constexpr double kCrackClose = 0.0005;

}  // namespace

std::vector<Surface> detect_surfaces(const geom::TriangleSoup& soup, bool upward,
                                     const SurfaceOptions& options) {
  const double cos_max = std::cos(options.max_angle_deg * M_PI / 180.0);
  std::vector<Face> faces;
  for (const auto& t : soup.triangles) {
    const Eigen::Vector3d n = t.normal();
    if ((upward ? n.z() : -n.z()) <= cos_max) continue;
    Face f;
    f.z = (t.a.z() + t.b.z() + t.c.z()) / 3.0;
    f.xy = {t.a.head<2>(), t.b.head<2>(), t.c.head<2>()};
    f.area = std::abs(geom::signed_area(f.xy));
    if (f.area < 1e-10) continue;
    faces.push_back(std::move(f));
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.z < b.z; });

  std::vector<Surface> out;
  std::size_t begin = 0;
  while (begin < faces.size()) {
    // One level: consecutive heights that chain within the tolerance, spanning at most twice it.
    std::size_t end = begin + 1;
    while (end < faces.size() && faces[end].z - faces[end - 1].z <= options.height_tolerance &&
           faces[end].z - faces[begin].z <= 2.0 * options.height_tolerance) {
      ++end;
    }
    double level_area = 0.0;
    for (std::size_t i = begin; i < end; ++i) level_area += faces[i].area;
    if (level_area >= options.min_area) {
      std::vector<geom::Ring> rings;
      rings.reserve(end - begin);
      for (std::size_t i = begin; i < end; ++i) rings.push_back(faces[i].xy);
      const geom::Region merged =
          geom::offset(geom::offset(geom::unite_rings(rings), kCrackClose), -kCrackClose);
      for (geom::Region& piece : geom::components(merged)) {
        const double a = geom::area(piece);
        if (a < options.min_area) continue;
        // Height of this piece: faces whose centroid falls inside it.
        double zsum = 0.0, wsum = 0.0;
        for (std::size_t i = begin; i < end; ++i) {
          const geom::Point2 c = (faces[i].xy[0] + faces[i].xy[1] + faces[i].xy[2]) / 3.0;
          if (geom::contains(piece, c)) {
            zsum += faces[i].z * faces[i].area;
            wsum += faces[i].area;
          }
        }
        Surface s;
        s.height = wsum > 0.0 ? zsum / wsum : faces[begin].z;
        s.region = std::move(piece);
        s.area = a;
        out.push_back(std::move(s));
      }
    }
    begin = end;
  }
  std::sort(out.begin(), out.end(), [](const Surface& a, const Surface& b) {
    return a.height < b.height || (a.height == b.height && a.area > b.area);
  });
  return out;
}

}  // namespace mtg::graph
