// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <numbers>

namespace softbench::render {

/// The vertical field of view of camera_on_box's cameras, rad.
inline constexpr double kFieldOfView = 30.0 * std::numbers::pi / 180.0;

struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
};

/// A perspective camera aimed at a box: what every picture of one scene shares, so that two
/// models, or two instants, are seen from the same place at the same scale.
struct Camera {
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();        ///< world -> eye
  Eigen::Matrix4f projection = Eigen::Matrix4f::Identity();  ///< eye -> clip (OpenGL)

  Eigen::Matrix4f view_projection() const { return projection * view; }
  /// Where world point `p` lands in an image of `width` x `height` pixels (x right, y down, in
  /// pixels), the pixel convention of Image.
  Eigen::Vector2d pixel_of(const Eigen::Vector3d& p, int width, int height) const;
  /// The ray from the eye through `pixel` (pixel_of's convention), direction of unit length:
  /// what a click picks.
  Ray ray_through(const Eigen::Vector2d& pixel, int width, int height) const;
};

/// Looks at the box [lower, upper] from `direction` (from the box's centre towards the eye; any
/// length), z up, with a 30 degree vertical field of view, far enough that the box's bounding
/// sphere times `margin` fits both ways in an image of aspect `width / height`.
Camera camera_on_box(const Eigen::Vector3d& lower,
                     const Eigen::Vector3d& upper,
                     const Eigen::Vector3d& direction,
                     double aspect,
                     double margin = 1.15);

}  // namespace softbench::render
