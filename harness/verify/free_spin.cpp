// SPDX-License-Identifier: MIT
#include "harness/verify/free_spin.h"

#include "geometry/mesh_measures.h"
#include "models/model_registry.h"
#include "models/soft_body.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <memory>

namespace softbench::harness {

Eigen::Vector3d centre_of_mass(const Eigen::Matrix3Xd& x, const Eigen::VectorXd& masses) {
  return x * masses / masses.sum();
}

Eigen::Vector3d angular_momentum(const Eigen::Matrix3Xd& x,
                                 const Eigen::Matrix3Xd& v,
                                 const Eigen::VectorXd& masses) {
  const Eigen::Vector3d centre = centre_of_mass(x, masses);
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    momentum += masses(i) * (x.col(i) - centre).cross(v.col(i));
  }
  return momentum;
}

double rigid_fit_rms(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& rest) {
  const Eigen::Matrix4d fit = Eigen::umeyama(rest, x, /*with_scaling=*/false);
  const Eigen::Matrix3Xd placed =
      (fit.topLeftCorner<3, 3>() * rest).colwise() + fit.topRightCorner<3, 1>();
  return std::sqrt((x - placed).colwise().squaredNorm().mean());
}

nlohmann::json without_damping(const std::string& model, const nlohmann::json& overrides) {
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [key, value] : builtin_models().at(model).settling_damping.items()) {
    params[key] = 0.0;
  }
  params.update(overrides);
  return params;
}

SpinResult free_spin(const std::string& model,
                     const nlohmann::json& params,
                     const TetMesh& mesh,
                     const Material& material,
                     const SpinMotion& motion) {
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const Eigen::VectorXd masses = lumped_masses(mesh, material.density);
  const Eigen::Vector3d centre = centre_of_mass(rest, masses);
  const double diagonal = bounding_box_diagonal(rest);
  const Eigen::Vector3d omega = motion.rate * motion.axis.normalized();
  Eigen::Matrix3Xd velocities(3, rest.cols());
  for (Eigen::Index i = 0; i < rest.cols(); ++i) {
    velocities.col(i) = omega.cross(rest.col(i) - centre);
  }

  const std::unique_ptr<SoftBody> body =
      builtin_models().at(model).create(mesh, material, params, ParamSource{});
  body->set_velocities(velocities);
  const Eigen::Vector3d initial = angular_momentum(rest, velocities, masses);
  StepInput input;
  input.gravity.setZero();
  SpinResult result;
  const int steps = static_cast<int>(std::lround(motion.duration / motion.dt));
  for (int step = 0; step < steps; ++step) {
    if (!body->step(motion.dt, input).finite) {
      result.finite = false;
      return result;
    }
    result.steps_run = step + 1;
    const Eigen::Matrix3Xd& x = body->positions();
    result.momentum_drift = std::max(
        result.momentum_drift,
        (angular_momentum(x, body->velocities(), masses) - initial).norm() / initial.norm());
    result.shape_error = std::max(result.shape_error, rigid_fit_rms(x, rest) / diagonal);
    result.centre_drift =
        std::max(result.centre_drift, (centre_of_mass(x, masses) - centre).norm() / diagonal);
  }
  return result;
}

}  // namespace softbench::harness
