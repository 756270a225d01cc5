// SPDX-License-Identifier: MIT
#include "models/bullet/bullet_energy.h"

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

double stable_neo_hookean_density(const Eigen::Matrix3d& deformation_gradient,
                                  double mu,
                                  double lambda) {
  // psi(F) - psi(I) = mu/2 [x - log1p(x)] + 3 mu/8 [a - 2 (J - 1)] + lambda/2 (J - 1)^2 with
  // a = tr G, x = a / 4, G = C - I. With q = (tr^2 G - tr G^2) / 2 + det G, det C = 1 + a + q,
  // so for J > 0: J - 1 = (a + q) / (J + 1) and a - 2 (J - 1) = (a (J - 1) - 2 q) / (J + 1),
  // both free of cancellation.
  const Eigen::Matrix3d& F = deformation_gradient;
  const Eigen::Matrix3d G = F.transpose() * F - Eigen::Matrix3d::Identity();
  const double a = G.trace();
  const double J = F.determinant();
  double j_minus_1 = 0.0;
  double volume_term = 0.0;  // a - 2 (J - 1)
  if (J > 0.0) {
    const double q = 0.5 * (a * a - (G * G).trace()) + G.determinant();
    j_minus_1 = (a + q) / (J + 1.0);
    volume_term = (a * j_minus_1 - 2.0 * q) / (J + 1.0);
  } else {
    j_minus_1 = J - 1.0;
    volume_term = a - 2.0 * j_minus_1;
  }
  const double x = 0.25 * a;
  return 0.5 * mu * (x - std::log1p(x)) + 0.375 * mu * volume_term
         + 0.5 * lambda * j_minus_1 * j_minus_1;
}

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
             ? stable_neo_hookean_density(deformation_gradient, mu_, lambda_)
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
