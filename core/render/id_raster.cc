#include "core/render/id_raster.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/util/error.h"

namespace mtg::render {
namespace {

// Four floats or ints (GCC's vector extension: SSE2 on x86-64, NEON on arm64). The build
// targets baseline x86-64, which has no fused multiply-add: each lane rounds as the scalar
// code does (a target with FMA would want -ffp-contract=off for the pass's pixels to stay put).
using F4 = float __attribute__((vector_size(16)));
using I4 = std::int32_t __attribute__((vector_size(16)));
constexpr I4 kLanes = {0, 1, 2, 3};

// Screen coordinates are clamped this far outside the image before rounding, so a pixel range
// always fits an int.
constexpr float kFar = 1e6f;

// Where the segment p-q meets the near plane z = -w (clip space).
Eigen::Vector4f near_crossing(const Eigen::Vector4f& p, const Eigen::Vector4f& q) {
  const float dp = p.z() + p.w(), dq = q.z() + q.w();
  const float t = dp / (dp - dq);
  return p + t * (q - p);
}

}  // namespace

IdImage::IdImage(int l, int t, int w, int h)
    : left(l),
      top(t),
      width(w),
      height(h),
      ids(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), kNone),
      depth(ids.size(), std::numeric_limits<float>::infinity()) {}

IdImage IdImage::unfilled(int l, int t, int w, int h) {
  IdImage out;
  out.left = l;
  out.top = t;
  out.width = w;
  out.height = h;
  out.ids.reserve(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  out.depth.reserve(out.ids.capacity());
  return out;
}

IdImage IdImage::window(int l, int t, int w, int h) const {
  MTG_DEMAND(l >= left && t >= top && l + w <= left + width && t + h <= top + height && w >= 0 && h >= 0,
             "id image: the window is not inside the image");
  IdImage out = unfilled(l, t, w, h);
  append_window(ids, left, top, width, l, t, w, h, out.ids);
  append_window(depth, left, top, width, l, t, w, h, out.depth);
  return out;
}

Camera at_resolution(const Camera& camera, int width, int height) {
  Camera c = camera;
  c.width = width;
  c.height = height;
  return c;
}

bool may_show(const Eigen::Matrix4f& clip_from_world, const Eigen::AlignedBox3d& box_W) {
  if (box_W.isEmpty()) return false;
  // Bits of the frustum sides each corner lies outside; a box is out when all corners share one.
  unsigned all_out = 0x3f;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner = box_W.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k));
    const Eigen::Vector4f c = clip_from_world * Eigen::Vector4f(static_cast<float>(corner.x()),
                                                                static_cast<float>(corner.y()),
                                                                static_cast<float>(corner.z()), 1.0f);
    unsigned out = 0;
    out |= c.x() < -c.w() ? 1u : 0u;
    out |= c.x() > c.w() ? 2u : 0u;
    out |= c.y() < -c.w() ? 4u : 0u;
    out |= c.y() > c.w() ? 8u : 0u;
    out |= c.z() < -c.w() ? 16u : 0u;
    out |= c.z() > c.w() ? 32u : 0u;
    all_out &= out;
  }
  return all_out == 0;
}

Splat splat_of(const Camera& camera, const ObjectTriangles& t, const Eigen::Isometry3d& X_WO) {
  // The window of its vertices' pixels, with the arithmetic of fill_triangle (a triangle's pixels
  // lie inside its vertices' box), a pixel wider all round; the whole image where a vertex lies
  // behind the near plane (clipping makes new vertices) or projects to no number or far off.
  const Eigen::Matrix4f M = camera.clip_from_world() * X_WO.matrix().cast<float>();
  const float W = static_cast<float>(camera.width), H = static_cast<float>(camera.height);
  float x0 = std::numeric_limits<float>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  bool whole = false;
  for (const Eigen::Vector3f& p : t.vertices_O) {
    const Eigen::Vector4f c = M * Eigen::Vector4f(p.x(), p.y(), p.z(), 1.0f);
    if (!(c.z() + c.w() >= 0.0f) || !(c.w() > 0.0f)) {
      whole = true;
      break;
    }
    const float iw = 1.0f / c.w();
    const float x = (c.x() * iw + 1.0f) * 0.5f * W, y = (1.0f - c.y() * iw) * 0.5f * H;
    if (!(std::abs(x) < kFar) || !(std::abs(y) < kFar)) {  // fill_triangle clamps there
      whole = true;
      break;
    }
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  int left = 0, top = 0, right = camera.width, bottom = camera.height;  // right, bottom: past the end
  if (!whole) {
    if (t.vertices_O.empty() || x1 < -1.0f || y1 < -1.0f || x0 > W + 1.0f || y0 > H + 1.0f) return {};
    left = std::max(0, static_cast<int>(std::floor(x0)) - 1);
    top = std::max(0, static_cast<int>(std::floor(y0)) - 1);
    right = std::min(camera.width, static_cast<int>(std::ceil(x1)) + 2);
    bottom = std::min(camera.height, static_cast<int>(std::ceil(y1)) + 2);
    if (left >= right || top >= bottom) return {};
  }
  IdPass pass(camera, IdImage(left, top, right - left, bottom - top));
  pass.draw(t, X_WO, 0);
  Splat out;
  const IdImage& image = pass.image();
  for (int v = 0; v < image.height; ++v) {
    const std::size_t row = static_cast<std::size_t>(v) * static_cast<std::size_t>(image.width);
    for (int u = 0; u < image.width; ++u) {
      if (!pass.covered_by_last_draw(row + static_cast<std::size_t>(u))) continue;
      const bool goes_on = !out.runs.empty() && out.runs.back().v == top + v &&
                           out.runs.back().u + out.runs.back().length == left + u;
      if (goes_on) {
        ++out.runs.back().length;
      } else {
        out.runs.push_back({top + v, left + u, 1});
      }
      out.depth.push_back(image.depth[row + static_cast<std::size_t>(u)]);
    }
  }
  return out;
}

int composite(const Splat& splat, std::int32_t id, IdImage& image) {
  int covered = 0;
  std::size_t k = 0;  // the depth of the run's first pixel
  for (const Splat::Run& run : splat.runs) {
    const std::size_t first = k;
    k += static_cast<std::size_t>(run.length);
    const int v = run.v - image.top;
    if (v < 0 || v >= image.height) continue;
    const int u0 = std::max(run.u, image.left), u1 = std::min(run.u + run.length, image.left + image.width);
    const std::size_t row = static_cast<std::size_t>(v) * static_cast<std::size_t>(image.width);
    for (int u = u0; u < u1; ++u) {
      const float z = splat.depth[first + static_cast<std::size_t>(u - run.u)];
      const std::size_t i = row + static_cast<std::size_t>(u - image.left);
      if (z < image.depth[i]) {
        image.depth[i] = z;
        image.ids[i] = id;
      }
    }
    covered += std::max(0, u1 - u0);
  }
  return covered;
}

IdPass::IdPass(const Camera& camera) : IdPass(camera, IdImage(camera.width, camera.height)) {}

IdPass::IdPass(const Camera& camera, IdImage background)
    : clip_from_world_(camera.clip_from_world()),
      full_width_(camera.width),
      full_height_(camera.height),
      image_(std::move(background)),
      stamp_(image_.ids.size(), 0) {
  MTG_DEMAND(image_.left >= 0 && image_.top >= 0 && image_.left + image_.width <= camera.width &&
                 image_.top + image_.height <= camera.height,
             "id pass: the background is not a window of the camera's image");
}

int IdPass::draw(const ObjectTriangles& t, const Eigen::Isometry3d& X_WO, std::int32_t id) {
  ++draw_count_;
  const Eigen::Matrix4f M = clip_from_world_ * X_WO.matrix().cast<float>();
  clip_.resize(t.vertices_O.size());
  for (std::size_t v = 0; v < t.vertices_O.size(); ++v) {
    const Eigen::Vector3f& p = t.vertices_O[v];
    clip_[v] = M * Eigen::Vector4f(p.x(), p.y(), p.z(), 1.0f);
  }
  int covered = 0;
  for (std::size_t k = 0; k + 2 < t.indices.size(); k += 3) {
    const Eigen::Vector4f& a = clip_[t.indices[k]];
    const Eigen::Vector4f& b = clip_[t.indices[k + 1]];
    const Eigen::Vector4f& c = clip_[t.indices[k + 2]];
    // Wholly outside one side of the frustum: nothing to draw.
    if ((a.x() > a.w() && b.x() > b.w() && c.x() > c.w()) || (a.x() < -a.w() && b.x() < -b.w() && c.x() < -c.w()) ||
        (a.y() > a.w() && b.y() > b.w() && c.y() > c.w()) || (a.y() < -a.w() && b.y() < -b.w() && c.y() < -c.w()) ||
        (a.z() > a.w() && b.z() > b.w() && c.z() > c.w())) {
      continue;
    }
    const bool in_a = a.z() + a.w() >= 0.0f, in_b = b.z() + b.w() >= 0.0f, in_c = c.z() + c.w() >= 0.0f;
    if (in_a && in_b && in_c) {
      fill_triangle(a, b, c, id, covered);
      continue;
    }
    if (!in_a && !in_b && !in_c) continue;
    // Clip against the near plane (Sutherland-Hodgman with one plane), then draw the fan.
    const Eigen::Vector4f in[3] = {a, b, c};
    const bool inside[3] = {in_a, in_b, in_c};
    Eigen::Vector4f poly[4];
    int n = 0;
    for (int e = 0; e < 3; ++e) {
      const int f = (e + 1) % 3;
      if (inside[e]) poly[n++] = in[e];
      if (inside[e] != inside[f]) poly[n++] = near_crossing(in[e], in[f]);
    }
    for (int k2 = 1; k2 + 1 < n; ++k2) fill_triangle(poly[0], poly[k2], poly[k2 + 1], id, covered);
  }
  return covered;
}

void IdPass::fill_triangle(const Eigen::Vector4f& a4, const Eigen::Vector4f& b4, const Eigen::Vector4f& c4,
                           std::int32_t id, int& covered) {
  const float W = static_cast<float>(full_width_), H = static_cast<float>(full_height_);
  // Pixel coordinates in the camera's image (the same arithmetic whatever the window, so a window
  // holds exactly the pixels a whole pass has there).
  auto screen = [&](const Eigen::Vector4f& p) {
    const float iw = 1.0f / p.w();
    return Eigen::Vector3f((p.x() * iw + 1.0f) * 0.5f * W, (1.0f - p.y() * iw) * 0.5f * H, p.z() * iw);
  };
  Eigen::Vector3f a = screen(a4), b = screen(b4), c = screen(c4);
  float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  if (!(std::abs(area) > 1e-12f)) return;  // degenerate (or NaN)
  if (area < 0.0f) {
    std::swap(b, c);
    area = -area;
  }
  const float min_x = std::max(-kFar, std::min({a.x(), b.x(), c.x()}));
  const float max_x = std::min(kFar, std::max({a.x(), b.x(), c.x()}));
  const float min_y = std::max(-kFar, std::min({a.y(), b.y(), c.y()}));
  const float max_y = std::min(kFar, std::max({a.y(), b.y(), c.y()}));
  // Pixels whose centre (u + 0.5, v + 0.5) may lie inside.
  const int u0 = std::max(image_.left, static_cast<int>(std::ceil(min_x - 0.5f)));
  const int u1 = std::min(image_.left + image_.width - 1, static_cast<int>(std::floor(max_x - 0.5f)));
  const int v0 = std::max(image_.top, static_cast<int>(std::ceil(min_y - 0.5f)));
  const int v1 = std::min(image_.top + image_.height - 1, static_cast<int>(std::floor(max_y - 0.5f)));
  if (u0 > u1 || v0 > v1) return;
  // Edge functions e(p) = (q1 - q0) x (p - q0), all positive inside once the area is positive.
  const float e0x = b.y() - c.y(), e0y = c.x() - b.x();  // edge b->c; weight of a
  const float e1x = c.y() - a.y(), e1y = a.x() - c.x();  // edge c->a; weight of b
  const float e2x = a.y() - b.y(), e2y = b.x() - a.x();  // edge a->b; weight of c
  const float inv_area = 1.0f / area;
  const std::uint32_t stamp = draw_count_;
  for (int v = v0; v <= v1; ++v) {
    const float py = static_cast<float>(v) + 0.5f;
    // The row's span inside all three edges, a pixel wider each way (only a shortcut: each pixel
    // is still decided by the test below, so the pixels are the same without it).
    float lo = -std::numeric_limits<float>::infinity(), hi = std::numeric_limits<float>::infinity();
    bool empty = false;
    const auto bound = [&](float qx, float qy, float ex, float ey) {
      const float offset = (py - qy) * ey - qx * ex;  // w(px) = offset + ex * px
      if (ex > 0.0f) {
        lo = std::max(lo, -offset / ex);
      } else if (ex < 0.0f) {
        hi = std::min(hi, -offset / ex);
      } else if (offset < 0.0f) {
        empty = true;
      }
    };
    bound(b.x(), b.y(), e0x, e0y);
    bound(c.x(), c.y(), e1x, e1y);
    bound(a.x(), a.y(), e2x, e2y);
    if (empty || !(lo <= hi + 2.0f)) continue;
    const int su0 = std::max(u0, lo > static_cast<float>(u0) ? static_cast<int>(std::floor(lo - 0.5f)) - 1 : u0);
    const int su1 = std::min(u1, hi < static_cast<float>(u1) ? static_cast<int>(std::ceil(hi - 0.5f)) + 1 : u1);
    const float r0 = (py - b.y()) * e0y, r1 = (py - c.y()) * e1y, r2 = (py - a.y()) * e2y;
    const std::size_t row = static_cast<std::size_t>(v - image_.top) * static_cast<std::size_t>(image_.width);
    const int row_end = image_.left + image_.width;
    int u = su0;
    // Four pixels at a time while the row holds four more: the same float operations per pixel as
    // the one-pixel loop after it (no fused multiply-add, same order), so the same bits; pixels
    // past su1 are read and written back unchanged.
    for (; u <= su1 && u + 4 <= row_end; u += 4) {
      const I4 us = u + kLanes;
      const F4 px = __builtin_convertvector(us, F4) + 0.5f;
      const F4 w0 = (px - b.x()) * e0x + r0;
      const F4 w1 = (px - c.x()) * e1x + r1;
      const F4 w2 = (px - a.x()) * e2x + r2;
      const F4 z = (w0 * a.z() + w1 * b.z() + w2 * c.z()) * inv_area;
      const I4 in = (us <= su1) & ~((w0 < 0.0f) | (w1 < 0.0f) | (w2 < 0.0f) | (z < -1.0f) | (z > 1.0f));
      if (!(in[0] | in[1] | in[2] | in[3])) continue;
      const std::size_t i = row + static_cast<std::size_t>(u - image_.left);
      I4 stamps, ids;
      F4 depths;
      std::memcpy(&stamps, &stamp_[i], sizeof stamps);
      std::memcpy(&depths, &image_.depth[i], sizeof depths);
      std::memcpy(&ids, &image_.ids[i], sizeof ids);
      const I4 fresh = in & (stamps != static_cast<std::int32_t>(stamp));
      covered -= fresh[0] + fresh[1] + fresh[2] + fresh[3];  // a true lane is -1
      stamps = in ? static_cast<std::int32_t>(stamp) : stamps;
      const I4 nearer = in & (z < depths);
      depths = nearer ? z : depths;
      ids = nearer ? id : ids;
      std::memcpy(&stamp_[i], &stamps, sizeof stamps);
      std::memcpy(&image_.depth[i], &depths, sizeof depths);
      std::memcpy(&image_.ids[i], &ids, sizeof ids);
    }
    for (; u <= su1; ++u) {
      const float px = static_cast<float>(u) + 0.5f;
      const float w0 = (px - b.x()) * e0x + r0;
      const float w1 = (px - c.x()) * e1x + r1;
      const float w2 = (px - a.x()) * e2x + r2;
      if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;
      const float z = (w0 * a.z() + w1 * b.z() + w2 * c.z()) * inv_area;
      if (z < -1.0f || z > 1.0f) continue;
      const std::size_t i = row + static_cast<std::size_t>(u - image_.left);
      if (stamp_[i] != stamp) {
        stamp_[i] = stamp;
        ++covered;
      }
      if (z < image_.depth[i]) {
        image_.depth[i] = z;
        image_.ids[i] = id;
      }
    }
  }
}

}  // namespace mtg::render
