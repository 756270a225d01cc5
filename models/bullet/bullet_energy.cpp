// SPDX-License-Identifier: MIT
#include "models/bullet/bullet_energy.h"

#include "models/neo_hookean/stable_neo_hookean.h"
#include "models/rotation_svd.h"

#include <Eigen/LU>

#include <cmath>

namespace softbench::bullet {
namespace {

Eigen::Matrix3d edge_matrix(const Eigen::Matrix3Xd& x, const Eigen::Vector4i& tet) {
  Eigen::Matrix3d edges;
  edges << x.col(tet(1)) - x.col(tet(0)), x.col(tet(2)) - x.col(tet(0)),
      x.col(tet(3)) - x.col(tet(0));
  return edges;
}

}  // namespace

double corotated_density(const Eigen::Matrix3d& deformation_gradient, double mu, double lambda) {
  const RotationSvd svd = rotation_svd(deformation_gradient);
  const double j_minus_1 = deformation_gradient.determinant() - 1.0;
  return mu * (deformation_gradient - svd.u * svd.v.transpose()).squaredNorm()
         + 0.5 * lambda * j_minus_1 * j_minus_1;
}

ElasticEnergy::ElasticEnergy(
    Kind kind, const BulletMesh& mesh, double mu, double lambda, double spring_stiffness)
    : kind_(kind),
      mu_(mu),
      lambda_(lambda),
      spring_stiffness_(spring_stiffness),
      tets_(mesh.tets),
      edges_(mesh.edges) {
  const Eigen::Matrix3Xd& x = mesh.rest_positions;
  if (kind_ == Kind::kMassSpring) {
    rest_lengths_.resize(edges_.cols());
    for (Eigen::Index e = 0; e < edges_.cols(); ++e) {
      rest_lengths_(e) = (x.col(edges_(1, e)) - x.col(edges_(0, e))).norm();
    }
    return;
  }
  rest_inverse_.reserve(static_cast<std::size_t>(tets_.cols()));
  rest_volumes_.resize(tets_.cols());
  for (Eigen::Index t = 0; t < tets_.cols(); ++t) {
    const Eigen::Matrix3d rest = edge_matrix(x, tets_.col(t));
    rest_inverse_.push_back(rest.inverse());
    rest_volumes_(t) = rest.determinant() / 6.0;
  }
}

double ElasticEnergy::tet_energy(const Eigen::Matrix3d& deformation_gradient) const {
  return kind_ == Kind::kStableNeoHookean
             // Bullet's stable neo-Hookean density is Smith et al.'s with alpha = 1 + 3 mu / 4
             // lambda: the reference model's (round-off-safe) evaluation.
             ? neo_hookean::energy_density(deformation_gradient,
                                           {mu_, lambda_, 1.0 + 0.75 * mu_ / lambda_})
             : corotated_density(deformation_gradient, mu_, lambda_);
}

double ElasticEnergy::operator()(const Eigen::Matrix3Xd& positions) const {
  double energy = 0.0;
  if (kind_ == Kind::kMassSpring) {
    for (Eigen::Index e = 0; e < edges_.cols(); ++e) {
      const double stretch =
          (positions.col(edges_(1, e)) - positions.col(edges_(0, e))).norm() - rest_lengths_(e);
      energy += 0.5 * spring_stiffness_ * stretch * stretch;
    }
    return energy;
  }
  for (Eigen::Index t = 0; t < tets_.cols(); ++t) {
    const Eigen::Matrix3d F =
        edge_matrix(positions, tets_.col(t)) * rest_inverse_[static_cast<std::size_t>(t)];
    energy += rest_volumes_(t) * tet_energy(F);
  }
  return energy;
}

std::size_t ElasticEnergy::memory_bytes() const {
  return static_cast<std::size_t>(tets_.size() + edges_.size()) * sizeof(int)
         + rest_inverse_.size() * sizeof(Eigen::Matrix3d)
         + static_cast<std::size_t>(rest_volumes_.size() + rest_lengths_.size()) * sizeof(double);
}

}  // namespace softbench::bullet
