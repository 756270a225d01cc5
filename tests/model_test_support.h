// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/soft_body.h"

#include <Eigen/Core>

#include <span>
#include <vector>

// Constraint and input helpers every model's tests use: write each once.
namespace softbench::test {

/// Holds every vertex at `targets`.
inline std::vector<PositionConstraint> pin_all(const Eigen::Matrix3Xd& targets) {
  std::vector<PositionConstraint> pins;
  for (int v = 0; v < targets.cols(); ++v) {
    pins.push_back({v, targets.col(v), kExact});
  }
  return pins;
}

/// Exact pins on every vertex with x <= min x (+ a hair): one face of a box.
inline std::vector<PositionConstraint> pin_min_x_face(const TetMesh& mesh) {
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const double min_x = rest.row(0).minCoeff();
  std::vector<PositionConstraint> pins;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (rest(0, v) <= min_x + 1e-12) {
      pins.push_back({v, rest.col(v), kExact});
    }
  }
  return pins;
}

inline StepInput no_gravity(std::span<const PositionConstraint> constraints = {}) {
  StepInput input;
  input.gravity.setZero();
  input.constraints = constraints;
  return input;
}

/// Puts the body at `targets` with zero velocity: the first exact step lands it there, the
/// second holds it, leaving v = (target - target) / dt = 0 exactly.
inline void place_at_rest(SoftBody& body, const Eigen::Matrix3Xd& targets) {
  const std::vector<PositionConstraint> pins = pin_all(targets);
  constexpr double kDt = 0.01;
  body.step(kDt, no_gravity(pins));
  body.step(kDt, no_gravity(pins));
}

}  // namespace softbench::test
