// SPDX-License-Identifier: MIT
#include "models/neo_hookean/stable_neo_hookean.h"

#include "models/rotation_svd.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <array>
#include <cmath>

namespace softbench::neo_hookean {
namespace {

/// The cross-product matrix: skew(a) b = a x b.
Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d result;
  result << 0.0, -a.z(), a.y(),  //
      a.z(), 0.0, -a.x(),        //
      -a.y(), a.x(), 0.0;
  return result;
}

/// dJ/dF: the columns f1 x f2, f2 x f0, f0 x f1.
Eigen::Matrix3d cofactor(const Eigen::Matrix3d& f) {
  Eigen::Matrix3d result;
  result.col(0) = f.col(1).cross(f.col(2));
  result.col(1) = f.col(2).cross(f.col(0));
  result.col(2) = f.col(0).cross(f.col(1));
  return result;
}

}  // namespace

StableNeoHookean stable_neo_hookean(const LameParameters& lame) {
  StableNeoHookean law;
  law.mu = 4.0 / 3.0 * lame.mu;
  law.lambda = lame.lambda + 5.0 / 6.0 * lame.mu;
  law.alpha = 1.0 + 0.75 * law.mu / law.lambda;
  return law;
}

double energy_density(const Eigen::Matrix3d& deformation, const StableNeoHookean& law) {
  // With d = I_C - 3, j = J - 1 and beta = alpha - 1 = 3 mu / (4 lambda):
  //   Psi(F) - Psi(I) = mu/2 (d/4 - log(1 + d/4)) + lambda/2 j^2 + 3 mu / 4 (d/2 - j).
  // The first two terms are second order in the strain. The last one is too (d/2 = tr E and
  // j = tr E + O(E^2), E the Green strain), but only if d/2 and j come from the same E: computed
  // as tr(F^T F) - 3 and det F - 1 they each carry ~1e-16 of independent round-off even for a
  // rotation. So near J = 1, j = sqrt(det C) - 1 with det C = det(I + 2E) expanded in E.
  const Eigen::Matrix3d green =
      0.5 * (deformation.transpose() * deformation) - 0.5 * Eigen::Matrix3d::Identity();
  const double trace = green.trace();
  const double d = 2.0 * trace;
  const double det_f = deformation.determinant();
  double j = det_f - 1.0;
  if (std::abs(j) < 0.5) {
    // Near J = 1 only: there det C is in (1/4, 9/4) and its square root well conditioned (at
    // J ~ 0 it would turn det C's round-off of 1e-16 into 1e-8 in J).
    // det(I + 2E) - 1 = 2 tr E + 4 I2(E) + 8 det E, I2 the sum of principal 2x2 minors.
    const double minors = 0.5 * (trace * trace - (green * green).trace());
    const double x = 2.0 * trace + 4.0 * minors + 8.0 * green.determinant();
    j = x / (1.0 + std::sqrt(1.0 + x));  // sqrt(1 + x) - 1 without cancellation
  }
  const double quarter = 0.25 * d;
  return 0.5 * law.mu * (quarter - std::log1p(quarter)) + 0.5 * law.lambda * j * j
         + 0.75 * law.mu * (trace - j);
}

Eigen::Matrix3d first_piola(const Eigen::Matrix3d& deformation, const StableNeoHookean& law) {
  const double invariant = deformation.squaredNorm();
  const double j = deformation.determinant();
  return (law.mu * (1.0 - 1.0 / (invariant + 1.0))) * deformation
         + (law.lambda * (j - law.alpha)) * cofactor(deformation);
}

Matrix9d stress_derivative(const Eigen::Matrix3d& deformation, const StableNeoHookean& law) {
  const double invariant = deformation.squaredNorm();
  const double j = deformation.determinant();
  const Eigen::Matrix3d cof = cofactor(deformation);
  const Eigen::Map<const Vector9d> f(deformation.data());
  const Eigen::Map<const Vector9d> g(cof.data());

  Matrix9d hessian = (2.0 * law.mu / ((invariant + 1.0) * (invariant + 1.0))) * (f * f.transpose())
                     + law.lambda * (g * g.transpose());
  hessian.diagonal().array() += law.mu * (1.0 - 1.0 / (invariant + 1.0));

  // d^2J/dF^2: block (k, l) = d(cof column k)/d(column l), e.g. d(f1 x f2)/df1 = -skew(f2).
  const double scale = law.lambda * (j - law.alpha);
  const Eigen::Matrix3d s0 = scale * skew(deformation.col(0));
  const Eigen::Matrix3d s1 = scale * skew(deformation.col(1));
  const Eigen::Matrix3d s2 = scale * skew(deformation.col(2));
  hessian.block<3, 3>(0, 3) -= s2;
  hessian.block<3, 3>(0, 6) += s1;
  hessian.block<3, 3>(3, 0) += s2;
  hessian.block<3, 3>(3, 6) -= s0;
  hessian.block<3, 3>(6, 0) -= s1;
  hessian.block<3, 3>(6, 3) += s0;
  return hessian;
}

Matrix9d project_to_psd(const Matrix9d& hessian) {
  const Eigen::LLT<Matrix9d> cholesky(hessian);
  if (cholesky.info() == Eigen::Success) {
    return hessian;
  }
  const Eigen::SelfAdjointEigenSolver<Matrix9d> eigen(hessian);
  const Vector9d clamped = eigen.eigenvalues().cwiseMax(0.0);
  const Matrix9d scaled = eigen.eigenvectors() * clamped.asDiagonal();
  return scaled.lazyProduct(eigen.eigenvectors().transpose());
}

Matrix9d projected_stress_derivative(const Eigen::Matrix3d& deformation,
                                     const StableNeoHookean& law) {
  // F = U S V^T with rotations U, V (the sign of a reflection moved into s2, so S may have one
  // negative entry). Psi is isotropic, Psi(F) = Psi(U^T F V), so d^2Psi/dF^2 = Q H_S Q^T with
  // Q = V (x) U (vec(U A V^T) = Q vec(A)) and H_S the Hessian at the diagonal S. H_S couples
  // only {S00, S11, S22} among themselves and each pair {S_ij, S_ji}: its eigenproblem is one
  // 3x3 and three 2x2 symmetric ones, and Q H_S+ Q^T (H_S+ with clamped eigenvalues) is the
  // projection of the full Hessian (Q is orthogonal).
  const auto [u, v] = rotation_svd(deformation);
  // S = U^T F V, diagonal up to round-off (dropped).
  const Eigen::Matrix3d singular = (u.transpose() * deformation * v).diagonal().asDiagonal();
  Matrix9d diagonal_hessian = stress_derivative(singular, law);

  bool clamped = false;
  // The 3x3 block of the diagonal entries: vec indices 0, 4, 8.
  constexpr std::array<int, 3> kDiagonal{0, 4, 8};
  Eigen::Matrix3d scaling;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      scaling(a, b) = diagonal_hessian(kDiagonal[a], kDiagonal[b]);
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> scaling_eigen(scaling);
  if (scaling_eigen.eigenvalues().minCoeff() < 0.0) {
    clamped = true;
    scaling = scaling_eigen.eigenvectors() * scaling_eigen.eigenvalues().cwiseMax(0.0).asDiagonal()
              * scaling_eigen.eigenvectors().transpose();
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        diagonal_hessian(kDiagonal[a], kDiagonal[b]) = scaling(a, b);
      }
    }
  }
  // The 2x2 blocks of (S_ij, S_ji): vec indices (1, 3), (2, 6), (5, 7). [[a, b], [b, a]] has
  // the eigenvalues a + b and a - b with eigenvectors (1, 1)/sqrt 2 and (1, -1)/sqrt 2.
  constexpr std::array<std::array<int, 2>, 3> kPairs{{{1, 3}, {2, 6}, {5, 7}}};
  for (const auto& [first, second] : kPairs) {
    const double a = diagonal_hessian(first, first);
    const double d = diagonal_hessian(second, second);
    const double b = diagonal_hessian(first, second);
    const Eigen::Matrix2d block{{a, b}, {b, d}};
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> pair_eigen(block);
    if (pair_eigen.eigenvalues().minCoeff() < 0.0) {
      clamped = true;
      const Eigen::Matrix2d projected = pair_eigen.eigenvectors()
                                        * pair_eigen.eigenvalues().cwiseMax(0.0).asDiagonal()
                                        * pair_eigen.eigenvectors().transpose();
      diagonal_hessian(first, first) = projected(0, 0);
      diagonal_hessian(first, second) = projected(0, 1);
      diagonal_hessian(second, first) = projected(1, 0);
      diagonal_hessian(second, second) = projected(1, 1);
    }
  }
  if (!clamped) {
    return stress_derivative(deformation, law);
  }
  Matrix9d rotation;  // V (x) U
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) {
      rotation.block<3, 3>(3 * k, 3 * l) = v(k, l) * u;
    }
  }
  const Matrix9d half = rotation.lazyProduct(diagonal_hessian);
  Matrix9d projected = half.lazyProduct(rotation.transpose());
  return 0.5 * (projected + projected.transpose());
}

}  // namespace softbench::neo_hookean
