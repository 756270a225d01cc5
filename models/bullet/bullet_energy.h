// SPDX-License-Identifier: MIT
#pragma once

// The elastic energies of Bullet 3.24's deformable forces, evaluated by the adapter from
// positions (Bullet's own totalElasticEnergy reads solver scratch, and for neo-Hookean does not
// vanish at rest). Eigen only: no Bullet types.
//
// Per tet, F = Ds Dm^-1 (Dm, Ds: edge matrices at rest and now), J = det F, C = F^T F:
// - stable neo-Hookean (Smith et al. 2018, with Bullet's constants):
//     psi = mu/2 (tr C - 3) + lambda/2 (J - 1 - 3 mu / (4 lambda))^2 - mu/2 log(tr C + 1),
//   reported relative to the rest state, psi(F) - psi(I), and evaluated from G = C - I so that
//   the terms linear in G cancel analytically: a rigid motion gives round-off squared, not
//   round-off times lambda;
// - corotated: psi = mu |F - R|^2 + lambda/2 (J - 1)^2, R the polar rotation of F;
// - mass-spring: 1/2 k (l - L)^2 per link.
// Energy = sum of rest volume x psi (tets) or the link terms, J.

#include "models/bullet/bullet_body.h"

#include <Eigen/Core>

#include <vector>

namespace softbench::bullet {

class ElasticEnergy {
 public:
  enum class Kind { kStableNeoHookean, kCorotated, kMassSpring };

  /// mu, lambda in Pa (tets); spring_stiffness in N/m (links).
  ElasticEnergy(
      Kind kind, const BulletMesh& mesh, double mu, double lambda, double spring_stiffness);

  /// J at `positions` (3 x #V).
  double operator()(const Eigen::Matrix3Xd& positions) const;

  std::size_t memory_bytes() const;

 private:
  double tet_energy(const Eigen::Matrix3d& deformation_gradient) const;

  Kind kind_;
  double mu_;
  double lambda_;
  double spring_stiffness_;
  Eigen::Matrix4Xi tets_;
  Eigen::Matrix2Xi edges_;
  std::vector<Eigen::Matrix3d> rest_inverse_;  ///< Dm^-1 per tet
  Eigen::VectorXd rest_volumes_;               ///< m^3 per tet
  Eigen::VectorXd rest_lengths_;               ///< m per link
};

/// Bullet's corotated energy density mu |F - R|^2 + lambda/2 (J - 1)^2, Pa.
double corotated_density(const Eigen::Matrix3d& deformation_gradient, double mu, double lambda);

}  // namespace softbench::bullet
