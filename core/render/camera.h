#pragma once
// A pinhole (or orthographic) camera in the world frame, with the projection both the GL
// rasteriser and the 2-D annotation overlay use, so marks land exactly on the rendered pixels.
//
// Frames: W world (Z-up). C camera, OpenGL convention: x right, y up, looking along -z.
// Pixels: (u, v) with (0, 0) the top-left corner of the image, v downwards.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

namespace mtg::render {

struct Camera {
  Eigen::Isometry3d X_WC = Eigen::Isometry3d::Identity();
  int width = 640;
  int height = 480;
  double fovy = 0.9;            // radians, vertical field of view (perspective)
  bool orthographic = false;
  double ortho_half_height = 1; // metres, half the visible height (orthographic)
  double near = 0.05;
  double far = 60.0;

  double aspect() const { return static_cast<double>(width) / height; }
  /// OpenGL clip-from-world matrix (projection * view).
  Eigen::Matrix4f clip_from_world() const;
  /// Pixel of a world point; nullopt when it lies behind the near plane.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_W) const;
};

/// A camera at `eye` looking at `target`, world z up (or `up` when looking straight down).
Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                          const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

}  // namespace mtg::render
