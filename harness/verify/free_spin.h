// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/material.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>

namespace softbench::harness {

// A body spinning in space, nothing held, no gravity, started with SoftBody::set_velocities:
// what the free-spin verification case and the models' free-spin tests measure.
//
// The axis should not be a principal axis of the body: its angular momentum L = I w is then not
// parallel to w, and w wanders while L must stay put. A model that kept w, or w's direction,
// instead of L passes a spin about a principal axis and fails this one.

/// Centre of mass of positions `x` (3 x #V) with lumped `masses` (#V).
Eigen::Vector3d centre_of_mass(const Eigen::Matrix3Xd& x, const Eigen::VectorXd& masses);
/// Angular momentum about the centre of mass, kg m^2/s.
Eigen::Vector3d angular_momentum(const Eigen::Matrix3Xd& x,
                                 const Eigen::Matrix3Xd& v,
                                 const Eigen::VectorXd& masses);
/// RMS distance of `x` to the best rigid placement of `rest` (Kabsch, unweighted, as the
/// recovery residual weighs vertices), m.
double rigid_fit_rms(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& rest);

/// `model`'s parameters with the damping its registry entry names (ModelInfo::settling_damping)
/// set to 0, `overrides` merged over them.
nlohmann::json without_damping(const std::string& model,
                               const nlohmann::json& overrides = nlohmann::json::object());

struct SpinMotion {
  double rate = 3.0;                                    ///< rad/s
  Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3);      ///< through the centre of mass
  double duration = 2.0;                                ///< s
  double dt = 1.0 / 60.0;                               ///< s
};

struct SpinResult {
  bool finite = true;           ///< false: a step reported a NaN or Inf (the rest is partial)
  int steps_run = 0;
  double momentum_drift = 0.0;  ///< largest |L(t) - L(0)| / |L(0)| over the steps
  double shape_error = 0.0;     ///< largest RMS distance to the rigid fit / rest bbox diagonal
  double centre_drift = 0.0;    ///< largest centre-of-mass displacement / rest bbox diagonal
};

/// Builds `model` on `mesh` with `params`, spins it rigidly about motion.axis through its
/// centre of mass at motion.rate and steps it freely (no gravity, no constraints) for
/// motion.duration. Throws InputError for an unknown model or a bad parameter block.
SpinResult free_spin(const std::string& model,
                     const nlohmann::json& params,
                     const TetMesh& mesh,
                     const Material& material,
                     const SpinMotion& motion);

}  // namespace softbench::harness
