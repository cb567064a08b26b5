#include "core/graph/topdown_png.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <map>

#include "core/render/png_writer.h"
#include "core/util/error.h"
#include "core/util/file_bytes.h"

namespace mtg::graph {
namespace {

const cv::Scalar kBackground(250, 250, 250);
const cv::Scalar kFurniture(90, 90, 90);
const cv::Scalar kScenery(170, 170, 170);
const cv::Scalar kNavigable(90, 190, 90);
const cv::Scalar kNotNavigable(80, 80, 220);
const cv::Scalar kStanding(235, 200, 140);  // BGR: light blue
const cv::Scalar kItem(40, 140, 240);  // BGR: orange
const cv::Scalar kText(30, 30, 30);

class Canvas {
 public:
  Canvas(const Eigen::AlignedBox2d& bounds, double ppm) : bounds_(bounds), ppm_(ppm) {
    const Eigen::Vector2d size = bounds.sizes() * ppm;
    image_ = cv::Mat(static_cast<int>(size.y()) + 1, static_cast<int>(size.x()) + 1, CV_8UC3, kBackground);
  }
  cv::Point px(const geom::Point2& p) const {
    return cv::Point(static_cast<int>((p.x() - bounds_.min().x()) * ppm_),
                     static_cast<int>((bounds_.max().y() - p.y()) * ppm_));  // y up
  }
  std::vector<cv::Point> poly(const geom::Ring& ring) const {
    std::vector<cv::Point> out;
    for (const auto& p : ring) out.push_back(px(p));
    return out;
  }
  void fill(const geom::Ring& ring, const cv::Scalar& colour, double alpha) {
    cv::Mat overlay = image_.clone();
    const auto pts = poly(ring);
    cv::fillPoly(overlay, std::vector<std::vector<cv::Point>>{pts}, colour, cv::LINE_AA);
    cv::addWeighted(overlay, alpha, image_, 1.0 - alpha, 0.0, image_);
  }
  void outline(const geom::Ring& ring, const cv::Scalar& colour, int thickness) {
    cv::polylines(image_, std::vector<std::vector<cv::Point>>{poly(ring)}, true, colour, thickness, cv::LINE_AA);
  }
  void text(const std::string& s, const geom::Point2& at, double scale, const cv::Scalar& colour) {
    int baseline = 0;
    const cv::Size size = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline);
    const cv::Point p = px(at) - cv::Point(size.width / 2, -size.height / 2);
    cv::putText(image_, s, p, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(255, 255, 255), 3, cv::LINE_AA);
    cv::putText(image_, s, p, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
  }
  cv::Mat& image() { return image_; }

 private:
  Eigen::AlignedBox2d bounds_;
  double ppm_;
  cv::Mat image_;
};

geom::Point2 mean(const geom::Ring& ring) {
  geom::Point2 c = geom::Point2::Zero();
  for (const auto& p : ring) c += p;
  return ring.empty() ? c : geom::Point2(c / static_cast<double>(ring.size()));
}

}  // namespace

void write_topdown_png(const SceneGraph& g, const std::filesystem::path& file,
                       const TopdownOptions& options) {
  Eigen::AlignedBox2d bounds;
  for (const auto& o : g.objects) {
    if (o.kind == ObjectKind::kFurniture || o.kind == ObjectKind::kItem || o.kind == ObjectKind::kFixed) {
      for (const auto& p : o.footprint) bounds.extend(p);
    }
  }
  if (bounds.isEmpty()) bounds = Eigen::AlignedBox2d(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1));
  bounds.min() -= Eigen::Vector2d(0.8, 0.8);
  bounds.max() += Eigen::Vector2d(0.8, 0.8);
  Canvas canvas(bounds, options.pixels_per_metre);

  // Standing strips of usable sides (under everything else).
  for (const auto& p : g.platforms) {
    if (!p.navigable) continue;
    for (const auto& side : p.sides) {
      if (side.usable()) canvas.fill(side.strip_W, kStanding, 0.35);
    }
  }
  for (const auto& o : g.objects) {
    if (o.kind == ObjectKind::kFixed && !o.parent.valid() && o.bottom < 0.05) canvas.fill(o.footprint, kScenery, 0.5);
    if (o.kind == ObjectKind::kFurniture) canvas.fill(o.footprint, cv::Scalar(225, 225, 225), 1.0);
  }
  // Platforms: the top-most of each owner is what one sees from above; draw all, lowest first.
  const IdRange<PlatformId> ids = g.platforms.ids();
  std::vector<PlatformId> order(ids.begin(), ids.end());
  std::stable_sort(order.begin(), order.end(), [&](PlatformId a, PlatformId b) {
    return g.platforms[a].height < g.platforms[b].height;
  });
  for (const PlatformId pi : order) {
    const Platform& p = g.platforms[pi];
    if (!p.destination) continue;
    for (const auto& ring : p.polygon_W().rings) {
      if (geom::signed_area(ring) > 0) canvas.fill(ring, p.navigable ? kNavigable : kNotNavigable, 0.35);
    }
  }
  for (const auto& o : g.objects) {
    if (o.kind == ObjectKind::kFurniture) canvas.outline(o.footprint, kFurniture, 2);
  }
  for (const auto& o : g.objects) {
    if (o.kind == ObjectKind::kItem && o.parent.valid()) canvas.fill(o.footprint, kItem, 0.8);
    if (o.kind == ObjectKind::kFixed && o.parent.valid()) canvas.fill(o.footprint, kScenery, 0.8);
  }
  for (const auto& p : g.platforms) {
    if (!p.navigable) continue;
    for (const auto& side : p.sides) {
      if (side.usable()) cv::circle(canvas.image(), canvas.px(side.standing_point), 3, kStanding * 0.6, cv::FILLED, cv::LINE_AA);
    }
  }
  // One label per furniture: its name and the l-numbers of its navigable platforms.
  for (const auto& o : g.objects) {
    if (o.kind != ObjectKind::kFurniture) continue;
    std::vector<int> labels;
    for (const PlatformId pi : o.platforms) {
      if (g.platforms[pi].label > 0) labels.push_back(g.platforms[pi].label);
    }
    const geom::Point2 c = mean(o.footprint);
    canvas.text(o.name, c + geom::Point2(0, 0.08), 0.38, kText);
    if (!labels.empty()) {
      std::string l = navigation_key(labels.front());
      if (labels.size() > 1) l.append(1, '-').append(navigation_key(labels.back()));
      canvas.text(l, c - geom::Point2(0, 0.1), 0.5, cv::Scalar(20, 110, 20));
    }
  }
  cv::putText(canvas.image(), g.scene + ": green = navigable platform, red = not navigable, blue strips = standing areas, orange = items",
              cv::Point(10, 22), cv::FONT_HERSHEY_SIMPLEX, 0.5, kText, 1, cv::LINE_AA);
  // Through a rename, never through a link planted at the name (cv::imwrite followed it).
  write_file_bytes_atomically(file, render::encode_png(canvas.image()));
}

}  // namespace mtg::graph
