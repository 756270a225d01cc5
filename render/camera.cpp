// SPDX-License-Identifier: MIT
#include "render/camera.h"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace softbench::render {
Eigen::Vector2d Camera::pixel_of(const Eigen::Vector3d& p, int width, int height) const {
  const Eigen::Vector4f clip = view_projection() * Eigen::Vector4f(static_cast<float>(p.x()),
                                                                    static_cast<float>(p.y()),
                                                                    static_cast<float>(p.z()), 1.0F);
  const double x = clip.x() / clip.w();
  const double y = clip.y() / clip.w();
  return {(x + 1.0) * 0.5 * width, (1.0 - y) * 0.5 * height};
}

Ray Camera::ray_through(const Eigen::Vector2d& pixel, int width, int height) const {
  const Eigen::Matrix4d inverse = view_projection().cast<double>().inverse();
  const double x = 2.0 * pixel.x() / width - 1.0;
  const double y = 1.0 - 2.0 * pixel.y() / height;
  const Eigen::Vector4d near = inverse * Eigen::Vector4d(x, y, -1.0, 1.0);
  const Eigen::Vector4d far = inverse * Eigen::Vector4d(x, y, 1.0, 1.0);
  Ray ray;
  ray.origin = near.head<3>() / near.w();
  ray.direction = (far.head<3>() / far.w() - ray.origin).normalized();
  return ray;
}

Camera camera_on_box(const Eigen::Vector3d& lower,
                     const Eigen::Vector3d& upper,
                     const Eigen::Vector3d& direction,
                     double aspect,
                     double margin) {
  const Eigen::Vector3d centre = 0.5 * (lower + upper);
  const double radius = 0.5 * (upper - lower).norm() * margin;
  // The narrower of the two fields of view decides the distance.
  const double vertical = kFieldOfView;
  const double horizontal = 2.0 * std::atan(std::tan(0.5 * vertical) * aspect);
  const double distance = radius / std::sin(0.5 * std::min(vertical, horizontal));
  const Eigen::Vector3d forward = -direction.normalized();
  const Eigen::Vector3d eye = centre - distance * forward;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  if (std::abs(forward.dot(up)) > 0.99) {
    up = Eigen::Vector3d::UnitY();  // looking straight down or up
  }
  const Eigen::Vector3d right = forward.cross(up).normalized();
  const Eigen::Vector3d true_up = right.cross(forward);

  Camera camera;
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = right.transpose();
  view.block<1, 3>(1, 0) = true_up.transpose();
  view.block<1, 3>(2, 0) = -forward.transpose();
  view(0, 3) = -right.dot(eye);
  view(1, 3) = -true_up.dot(eye);
  view(2, 3) = forward.dot(eye);
  camera.view = view.cast<float>();

  const double near = std::max(distance - 4.0 * radius, 1e-3 * distance);
  const double far = distance + 4.0 * radius;
  const double f = 1.0 / std::tan(0.5 * vertical);
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  projection(0, 0) = f / aspect;
  projection(1, 1) = f;
  projection(2, 2) = (far + near) / (near - far);
  projection(2, 3) = 2.0 * far * near / (near - far);
  projection(3, 2) = -1.0;
  camera.projection = projection.cast<float>();
  return camera;
}

}  // namespace softbench::render
