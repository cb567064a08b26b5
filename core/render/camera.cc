#include "core/render/camera.h"

#include <cmath>

namespace mtg::render {

Eigen::Matrix4f Camera::clip_from_world() const {
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  const double n = near, f = far;
  if (orthographic) {
    const double t = ortho_half_height, r = t * aspect();
    P(0, 0) = 1.0 / r;
    P(1, 1) = 1.0 / t;
    P(2, 2) = -2.0 / (f - n);
    P(2, 3) = -(f + n) / (f - n);
    P(3, 3) = 1.0;
  } else {
    const double t = 1.0 / std::tan(fovy / 2.0);
    P(0, 0) = t / aspect();
    P(1, 1) = t;
    P(2, 2) = -(f + n) / (f - n);
    P(2, 3) = -2.0 * f * n / (f - n);
    P(3, 2) = -1.0;
  }
  return (P * X_WC.inverse().matrix()).cast<float>();
}

std::optional<Eigen::Vector2d> Camera::project(const Eigen::Vector3d& p_W) const {
  const Eigen::Vector3d p_C = X_WC.inverse() * p_W;
  double x = 0.0, y = 0.0;
  if (orthographic) {
    x = p_C.x() / (ortho_half_height * aspect());
    y = p_C.y() / ortho_half_height;
  } else {
    if (-p_C.z() < near) return std::nullopt;
    const double t = 1.0 / std::tan(fovy / 2.0);
    x = t / aspect() * p_C.x() / -p_C.z();
    y = t * p_C.y() / -p_C.z();
  }
  return Eigen::Vector2d((x + 1.0) / 2.0 * width, (1.0 - y) / 2.0 * height);
}

Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d forward = (target - eye).normalized();
  Eigen::Vector3d right = forward.cross(up);
  if (right.norm() < 1e-9) right = forward.cross(Eigen::Vector3d::UnitY());  // looking along `up`
  right.normalize();
  const Eigen::Vector3d cam_up = right.cross(forward);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear().col(0) = right;
  X.linear().col(1) = cam_up;
  X.linear().col(2) = -forward;
  X.translation() = eye;
  return X;
}

}  // namespace mtg::render
