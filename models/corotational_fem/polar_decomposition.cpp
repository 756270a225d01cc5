// SPDX-License-Identifier: MIT
#include "models/corotational_fem/polar_decomposition.h"

#include "models/rotation_svd.h"

#include <algorithm>
#include <cmath>

namespace softbench::corotational_fem {

Eigen::Matrix3d rotation_by_svd(const Eigen::Matrix3d& deformation) {
  const RotationSvd svd = rotation_svd(deformation);
  return svd.u * svd.v.transpose();
}

namespace {

constexpr int kLanes = kRotationLanes;

/// R(q) for a unit quaternion (w, x, y, z): column-major entries into r[9][lane].
inline void rotation_of(
    double qw, double qx, double qy, double qz, double (&r)[9][kLanes], int lane) {
  const double xx = qx * qx;
  const double yy = qy * qy;
  const double zz = qz * qz;
  const double xy = qx * qy;
  const double xz = qx * qz;
  const double yz = qy * qz;
  const double wx = qw * qx;
  const double wy = qw * qy;
  const double wz = qw * qz;
  r[0][lane] = 1.0 - 2.0 * (yy + zz);
  r[3][lane] = 2.0 * (xy - wz);
  r[6][lane] = 2.0 * (xz + wy);
  r[1][lane] = 2.0 * (xy + wz);
  r[4][lane] = 1.0 - 2.0 * (xx + zz);
  r[7][lane] = 2.0 * (yz - wx);
  r[2][lane] = 2.0 * (xz - wy);
  r[5][lane] = 2.0 * (yz + wx);
  r[8][lane] = 1.0 - 2.0 * (xx + yy);
}

}  // namespace

void extract_rotation_lanes(const double (&f)[9][kLanes],
                            std::span<Eigen::Quaterniond> rotations,
                            double (&r)[9][kLanes],
                            int max_iterations,
                            double tolerance) {
  constexpr double kDenominatorFloor = 1e-9;  // as extract_rotation()
  const double tolerance_squared = tolerance * tolerance;
  const auto count = static_cast<int>(rotations.size());
  double q[4][kLanes];  // (w, x, y, z); unused lanes at q = 1
  for (int lane = 0; lane < kLanes; ++lane) {
    const Eigen::Quaterniond start =
        lane < count ? rotations[static_cast<std::size_t>(lane)] : Eigen::Quaterniond::Identity();
    q[0][lane] = start.w();
    q[1][lane] = start.x();
    q[2][lane] = start.y();
    q[3][lane] = start.z();
  }
#pragma omp simd
  for (int lane = 0; lane < kLanes; ++lane) {
    rotation_of(q[0][lane], q[1][lane], q[2][lane], q[3][lane], r, lane);
  }
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    // Each lane's half-update h = w / 2, and the largest |w|^2 of the lanes.
    double h[3][kLanes];
    double largest = 0.0;
#pragma omp simd reduction(max : largest)
    for (int lane = 0; lane < kLanes; ++lane) {
      // torque = sum_c r_c x f_c, alignment = sum_c r_c . f_c over the columns c (written
      // out: an inner loop would keep the compiler from vectorising across lanes).
      const double r00 = r[0][lane], r01 = r[3][lane], r02 = r[6][lane];
      const double r10 = r[1][lane], r11 = r[4][lane], r12 = r[7][lane];
      const double r20 = r[2][lane], r21 = r[5][lane], r22 = r[8][lane];
      const double f00 = f[0][lane], f01 = f[3][lane], f02 = f[6][lane];
      const double f10 = f[1][lane], f11 = f[4][lane], f12 = f[7][lane];
      const double f20 = f[2][lane], f21 = f[5][lane], f22 = f[8][lane];
      const double tx = (r10 * f20 - r20 * f10) + (r11 * f21 - r21 * f11) + (r12 * f22 - r22 * f12);
      const double ty = (r20 * f00 - r00 * f20) + (r21 * f01 - r01 * f21) + (r22 * f02 - r02 * f22);
      const double tz = (r00 * f10 - r10 * f00) + (r01 * f11 - r11 * f01) + (r02 * f12 - r12 * f02);
      const double alignment = (r00 * f00 + r10 * f10 + r20 * f20)
                               + (r01 * f01 + r11 * f11 + r21 * f21)
                               + (r02 * f02 + r12 * f12 + r22 * f22);
      const double half_scale = 0.5 / (std::abs(alignment) + kDenominatorFloor);
      h[0][lane] = half_scale * tx;
      h[1][lane] = half_scale * ty;
      h[2][lane] = half_scale * tz;
      largest = std::max(
          largest,
          4.0 * (h[0][lane] * h[0][lane] + h[1][lane] * h[1][lane] + h[2][lane] * h[2][lane]));
    }
    if (!(largest >= tolerance_squared)) {  // every lane converged (or a NaN appeared)
      break;
    }
#pragma omp simd
    for (int lane = 0; lane < kLanes; ++lane) {
      // q <- (1, h) * q, normalised.
      const double qw = q[0][lane];
      const double qx = q[1][lane];
      const double qy = q[2][lane];
      const double qz = q[3][lane];
      const double hx = h[0][lane];
      const double hy = h[1][lane];
      const double hz = h[2][lane];
      double nw = qw - hx * qx - hy * qy - hz * qz;
      double nx = qx + hx * qw + hy * qz - hz * qy;
      double ny = qy - hx * qz + hy * qw + hz * qx;
      double nz = qz + hx * qy - hy * qx + hz * qw;
      const double inverse_norm = 1.0 / std::sqrt(nw * nw + nx * nx + ny * ny + nz * nz);
      nw *= inverse_norm;
      nx *= inverse_norm;
      ny *= inverse_norm;
      nz *= inverse_norm;
      q[0][lane] = nw;
      q[1][lane] = nx;
      q[2][lane] = ny;
      q[3][lane] = nz;
      rotation_of(nw, nx, ny, nz, r, lane);
    }
  }
  for (int lane = 0; lane < count; ++lane) {
    rotations[static_cast<std::size_t>(lane)] =
        Eigen::Quaterniond(q[0][lane], q[1][lane], q[2][lane], q[3][lane]);
  }
}

void extract_rotations(std::span<const Eigen::Matrix3d> deformations,
                       std::span<Eigen::Quaterniond> rotations,
                       std::span<Eigen::Matrix3d> matrices,
                       int max_iterations,
                       double tolerance) {
  constexpr auto kBatch = static_cast<std::size_t>(kLanes);
  for (std::size_t first = 0; first < deformations.size(); first += kBatch) {
    const std::size_t count = std::min(kBatch, deformations.size() - first);
    // Unused lanes hold F = 0.
    double f[9][kLanes];
    double r[9][kLanes];
    for (std::size_t lane = 0; lane < kBatch; ++lane) {
      for (int k = 0; k < 9; ++k) {
        f[k][lane] = lane < count ? deformations[first + lane].data()[k] : 0.0;
      }
    }
    extract_rotation_lanes(f, rotations.subspan(first, count), r, max_iterations, tolerance);
    for (std::size_t lane = 0; lane < count; ++lane) {
      for (int k = 0; k < 9; ++k) {
        matrices[first + lane].data()[k] = r[k][lane];
      }
    }
  }
}

}  // namespace softbench::corotational_fem
