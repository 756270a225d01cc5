// SPDX-License-Identifier: MIT
// Per-cluster shape matching (Mueller et al. 2005, sections 3-4 and the quadratic extension of
// 4.2): the rest-shape precomputation and the allocation-free per-step kernel.
#include "models/shape_matching/cluster_matching.h"

#include "models/shape_matching/rotation_extraction.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

namespace softbench::shape_matching {
namespace {

/// Eigenvalues of the scaled moment matrix Aqq below this fraction of the largest are treated
/// as zero in its pseudo-inverse: the basis is O(1) after scaling, so only directions a flat or
/// tiny cluster does not span (exact zeros up to round-off) fall under it.
constexpr double kPseudoInverseCutoff = 1e-9;

/// Linear mode: A / cbrt(det A) only while det A exceeds this (the cluster keeps more than 5% of
/// its volume); below, the cluster follows R alone, since A / cbrt(det A) grows without bound
/// as det A -> 0 and has no meaning for det A < 0.
constexpr double kMinVolumeRatio = 0.05;

/// Below this many memberships a match runs on one thread: the parallel region costs more than
/// it saves.
constexpr int kParallelMemberships = 2048;

/// The basis of a scaled rest offset q: q itself (D = 3), or q~ = [qx qy qz qx^2 qy^2 qz^2
/// qx qy  qy qz  qz qx] (D = 9, the thesis's eq. 3-43 order).
template <int D>
Eigen::Matrix<double, D, 1> monomials(const Eigen::Vector3d& q) {
  Eigen::Matrix<double, D, 1> basis;
  basis.template head<3>() = q;
  if constexpr (D == 9) {
    basis.template segment<3>(3) = q.cwiseAbs2();
    basis(6) = q.x() * q.y();
    basis(7) = q.y() * q.z();
    basis(8) = q.z() * q.x();
  }
  return basis;
}

/// Two doubles as one value (GCC/Clang vector extension): an SSE2 register on x86-64, a NEON
/// one on AArch64. The moment loop spells its two partial sums out in this type, because GCC
/// otherwise vectorises it across the nine accumulators, with shuffles and spills.
using Pair = double __attribute__((vector_size(2 * sizeof(double))));

Pair load_pair(const double* values) {
  Pair pair;
  std::memcpy(&pair, values, sizeof(pair));
  return pair;
}

/// sum_j p_r[j] b_c[j] for r, c in 0..2: nine dot products in one pass over the rows, each as
/// two partial sums (even and odd j) added at the end: a fixed summation order, so the result
/// does not depend on alignment or threads.
Eigen::Matrix3d moments(const double* px,
                        const double* py,
                        const double* pz,
                        const double* b0,
                        const double* b1,
                        const double* b2,
                        int n) {
  Pair sums[9] = {};
  int j = 0;
  for (; j + 2 <= n; j += 2) {
    const Pair x = load_pair(px + j);
    const Pair y = load_pair(py + j);
    const Pair z = load_pair(pz + j);
    const Pair u = load_pair(b0 + j);
    const Pair v = load_pair(b1 + j);
    const Pair w = load_pair(b2 + j);
    sums[0] += x * u;
    sums[1] += x * v;
    sums[2] += x * w;
    sums[3] += y * u;
    sums[4] += y * v;
    sums[5] += y * w;
    sums[6] += z * u;
    sums[7] += z * v;
    sums[8] += z * w;
  }
  Eigen::Matrix3d result;
  for (int e = 0; e < 9; ++e) {
    result(e / 3, e % 3) = sums[e][0] + sums[e][1];
  }
  if (j < n) {  // an odd count: the last term
    result(0, 0) += px[j] * b0[j];
    result(0, 1) += px[j] * b1[j];
    result(0, 2) += px[j] * b2[j];
    result(1, 0) += py[j] * b0[j];
    result(1, 1) += py[j] * b1[j];
    result(1, 2) += py[j] * b2[j];
    result(2, 0) += pz[j] * b0[j];
    result(2, 1) += pz[j] * b1[j];
    result(2, 2) += pz[j] * b2[j];
  }
  return result;
}

/// out[j] = centre + sum_d t(d) basis[d n + j]: one coordinate of the goals (vectorised over j;
/// `out` must not overlap `basis`).
template <int D>
void goal_row(const Eigen::Matrix<double, 1, D>& t,
              double centre,
              const double* __restrict basis,
              int n,
              double* __restrict out) {
  double coefficients[D];
  for (int d = 0; d < D; ++d) {
    coefficients[d] = t(d);
  }
  for (int j = 0; j < n; ++j) {
    double goal = centre;
    for (int d = 0; d < D; ++d) {
      goal += coefficients[d] * basis[d * n + j];
    }
    out[j] = goal;
  }
}

/// The Moore-Penrose pseudo-inverse of a symmetric positive semi-definite matrix.
template <int D>
Eigen::Matrix<double, D, D> pseudo_inverse(const Eigen::Matrix<double, D, D>& moment) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> eigen(moment);
  const Eigen::Matrix<double, D, 1>& values = eigen.eigenvalues();
  const double cutoff = kPseudoInverseCutoff * values.cwiseAbs().maxCoeff();
  Eigen::Matrix<double, D, 1> inverse_values;
  for (int d = 0; d < D; ++d) {
    inverse_values(d) = values(d) > cutoff && values(d) > 0.0 ? 1.0 / values(d) : 0.0;
  }
  return eigen.eigenvectors() * inverse_values.asDiagonal() * eigen.eigenvectors().transpose();
}

}  // namespace

ClusterMatcher::ClusterMatcher(const Eigen::Matrix3Xd& rest,
                               const Eigen::VectorXd& masses,
                               const Clusters& clusters,
                               const ShapeMatchingParams& params)
    : params_(params), dim_(params.type == ShapeMatchingParams::Type::kLinear ? 3 : 9) {
  assert(masses.size() == rest.cols());
  if (dim_ == 3) {
    precompute<3>(rest, masses, clusters);
  } else {
    precompute<9>(rest, masses, clusters);
  }
  reference_ = rest_centres_;

  // Each particle's memberships, in increasing membership (so cluster) order.
  const int num_particles = static_cast<int>(rest.cols());
  particle_offsets_.assign(index(num_particles) + 1, 0);
  for (const int particle : member_particle_) {
    ++particle_offsets_[index(particle) + 1];
  }
  for (int i = 0; i < num_particles; ++i) {
    particle_offsets_[index(i) + 1] += particle_offsets_[index(i)];
  }
  slot_start_.resize(member_particle_.size());
  slot_stride_.resize(member_particle_.size());
  std::vector<int> next(particle_offsets_.begin(), particle_offsets_.end() - 1);
  for (int k = 0; k < num_clusters(); ++k) {
    const int begin = cluster_begin(k);
    const int size = cluster_end(k) - begin;
    for (int m = begin; m < cluster_end(k); ++m) {
      const int slot = next[index(member_particle_[index(m)])]++;
      slot_start_[index(slot)] = 3 * static_cast<std::ptrdiff_t>(begin) + (m - begin);
      slot_stride_[index(slot)] = size;
    }
  }
  inverse_count_.resize(num_particles);
  for (int i = 0; i < num_particles; ++i) {
    const int count = particle_offsets_[index(i) + 1] - particle_offsets_[index(i)];
    assert(count > 0 && "every particle must be in a cluster");
    inverse_count_(i) = 1.0 / count;
  }
}

template <int D>
void ClusterMatcher::precompute(const Eigen::Matrix3Xd& rest,
                                const Eigen::VectorXd& masses,
                                const Clusters& clusters) {
  const int count = clusters.count();
  const std::size_t memberships = clusters.members.size();
  member_particle_ = clusters.members;
  member_weight_.resize(memberships);
  basis_.resize(D * memberships);
  work_.assign(3 * memberships, 0.0);
  cluster_offsets_ = clusters.offsets;
  scale_.resize(index(count));
  moment_inverse_.resize(index(count) * D * D);
  rotations_.assign(index(count), Eigen::Quaterniond::Identity());
  rest_centres_.resize(3 * index(count));

  for (int k = 0; k < count; ++k) {
    const int begin = cluster_begin(k);
    const int size = cluster_end(k) - begin;
    double mass = 0.0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int m = begin; m < begin + size; ++m) {
      const int i = member_particle_[index(m)];
      mass += masses(i);
      centre += masses(i) * rest.col(i);
    }
    centre /= mass;
    for (int axis = 0; axis < 3; ++axis) {
      rest_centres_[3 * index(k) + index(axis)] = centre(axis);
    }
    double spread = 0.0;
    for (int m = begin; m < begin + size; ++m) {
      const int i = member_particle_[index(m)];
      member_weight_[index(m)] = masses(i) / mass;
      spread += member_weight_[index(m)] * (rest.col(i) - centre).squaredNorm();
    }
    // One particle, or all at one point: no shape to match; any positive scale will do.
    const double scale = spread > 0.0 ? std::sqrt(spread) : 1.0;
    scale_[index(k)] = scale;

    // The basis rows, centred on their weighted mean (the linear rows' mean is zero up to
    // round-off; the quadratic rows' is not: centring gives the fit its intercept).
    double* block = basis_.data() + static_cast<std::ptrdiff_t>(D) * begin;
    Eigen::Matrix<double, D, 1> mean = Eigen::Matrix<double, D, 1>::Zero();
    for (int j = 0; j < size; ++j) {
      const int m = begin + j;
      const Eigen::Matrix<double, D, 1> b =
          monomials<D>((rest.col(member_particle_[index(m)]) - centre) / scale);
      for (int d = 0; d < D; ++d) {
        block[d * size + j] = b(d);
      }
      mean += member_weight_[index(m)] * b;
    }
    Eigen::Matrix<double, D, D> moment = Eigen::Matrix<double, D, D>::Zero();
    for (int j = 0; j < size; ++j) {
      Eigen::Matrix<double, D, 1> b;
      for (int d = 0; d < D; ++d) {
        block[d * size + j] -= mean(d);
        b(d) = block[d * size + j];
      }
      moment += member_weight_[index(begin + j)] * b * b.transpose();
    }
    Eigen::Map<Eigen::Matrix<double, D, D>>(moment_inverse_.data() + index(k) * D * D) =
        pseudo_inverse<D>(moment);
  }
}

int ClusterMatcher::match_cluster(int cluster, const Eigen::Matrix3Xd& positions) {
  return dim_ == 3 ? match_cluster_with<3>(cluster, positions)
                   : match_cluster_with<9>(cluster, positions);
}

template <int D>
int ClusterMatcher::match_cluster_with(int cluster, const Eigen::Matrix3Xd& positions) {
  const int begin = cluster_begin(cluster);
  const int n = cluster_end(cluster) - begin;
  const int* particle = member_particle_.data() + begin;
  const double* weight = member_weight_.data() + begin;
  const double* basis = basis_.data() + static_cast<std::ptrdiff_t>(D) * begin;
  double* px = work_.data() + 3 * static_cast<std::ptrdiff_t>(begin);
  double* py = px + n;
  double* pz = py + n;
  const double* x = positions.data();

  // One pass: the mass-weighted offsets m_i (x_i - r) / M from a reference point r near the
  // cluster (its centre of mass of the last match), and the centre of mass c = r + sum of
  // them. The basis rows have zero weighted mean, so sum m_i (x_i - r) b_i^T = sum m_i
  // (x_i - c) b_i^T: no second pass to subtract c; r only keeps the differences small.
  double* reference = reference_.data() + 3 * index(cluster);
  const double rx = reference[0];
  const double ry = reference[1];
  const double rz = reference[2];
  double dx = 0.0;
  double dy = 0.0;
  double dz = 0.0;
  for (int j = 0; j < n; ++j) {
    const double* xi = x + 3 * static_cast<std::ptrdiff_t>(particle[j]);
    px[j] = weight[j] * (xi[0] - rx);
    py[j] = weight[j] * (xi[1] - ry);
    pz[j] = weight[j] * (xi[2] - rz);
    dx += px[j];
    dy += py[j];
    dz += pz[j];
  }
  const double cx = rx + dx;
  const double cy = ry + dy;
  const double cz = rz + dz;
  reference[0] = cx;
  reference[1] = cy;
  reference[2] = cz;

  // Apq~ = sum m_i p_i b_i^T / M (3 x D), three basis rows at a time.
  Eigen::Matrix<double, 3, D> apq;
  for (int g = 0; g < D; g += 3) {
    apq.template middleCols<3>(g) =
        moments(px, py, pz, basis + g * n, basis + (g + 1) * n, basis + (g + 2) * n, n);
  }

  // The rotation of the linear part (the basis's linear rows are q / scale: same R).
  const Eigen::Matrix3d apq_linear = apq.template leftCols<3>();
  Eigen::Quaterniond& rotation = rotations_[index(cluster)];
  int iterations = 0;
  if (params_.rotation == ShapeMatchingParams::Rotation::kSvd) {
    rotation = Eigen::Quaterniond(polar_rotation_svd(apq_linear));
  } else {
    iterations = extract_rotation(apq_linear, rotation, params_.rotation_iterations);
  }
  const Eigen::Matrix3d r = rotation.toRotationMatrix();

  // T = beta A + (1 - beta) R (linear) or beta A~ + (1 - beta) [R 0 0] (quadratic), in the
  // scaled basis: the rigid map of a scaled offset q / s is s R.
  const double scale = scale_[index(cluster)];
  const double beta = params_.beta;
  // lazyProduct: a coefficient loop; the default product sends 3 x 9 * 9 x 9 to GEMM.
  const Eigen::Matrix<double, 3, D> fit =
      apq.lazyProduct(Eigen::Map<const Eigen::Matrix<double, D, D>>(moment_inverse_.data()
                                                                    + index(cluster) * D * D));
  Eigen::Matrix<double, 3, D> t;
  if constexpr (D == 3) {
    const Eigen::Matrix3d a = fit / scale;  // the physical A = Apq Aqq^-1
    const double det = a.determinant();
    if (beta > 0.0 && det > kMinVolumeRatio) {
      t = scale * (beta / std::cbrt(det) * a + (1.0 - beta) * r);
    } else {
      t = scale * r;
    }
  } else {
    t = beta * fit;
    t.template leftCols<3>() += ((1.0 - beta) * scale) * r;
  }

  // Goals g_j = T b_j + c, over the work rows (the offsets are no longer needed).
  goal_row<D>(t.row(0), cx, basis, n, px);
  goal_row<D>(t.row(1), cy, basis, n, py);
  goal_row<D>(t.row(2), cz, basis, n, pz);
  return iterations;
}

int ClusterMatcher::cluster_of_membership(int membership) const {
  return static_cast<int>(
             std::upper_bound(cluster_offsets_.begin(), cluster_offsets_.end(), membership)
             - cluster_offsets_.begin())
         - 1;
}

Eigen::Vector3d ClusterMatcher::membership_goal(int membership) const {
  const int cluster = cluster_of_membership(membership);
  const int begin = cluster_begin(cluster);
  const int size = cluster_end(cluster) - begin;
  const double* x = work_.data() + 3 * static_cast<std::ptrdiff_t>(begin) + (membership - begin);
  return {x[0], x[size], x[2 * size]};
}

int ClusterMatcher::match(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd& goals) {
  const int clusters = num_clusters();
  const int particles = num_particles();
  goals.resize(3, particles);
  int iterations = 0;
  [[maybe_unused]] const bool parallel = num_memberships() >= kParallelMemberships;
#pragma omp parallel if (parallel)
  {
#pragma omp for schedule(dynamic, 1) reduction(max : iterations)
    for (int k = 0; k < clusters; ++k) {
      iterations = std::max(iterations, match_cluster(k, positions));
    }
#pragma omp for schedule(dynamic, 256)
    for (int i = 0; i < particles; ++i) {
      goals.col(i) = goal(i);
    }
  }
  return iterations;
}

void ClusterMatcher::reset() {
  std::fill(rotations_.begin(), rotations_.end(), Eigen::Quaterniond::Identity());
  reference_ = rest_centres_;
}

std::size_t ClusterMatcher::memory_bytes() const {
  return member_particle_.size() * sizeof(int) + member_weight_.size() * sizeof(double)
         + basis_.size() * sizeof(double) + work_.size() * sizeof(double)
         + cluster_offsets_.size() * sizeof(int) + scale_.size() * sizeof(double)
         + moment_inverse_.size() * sizeof(double)
         + (rest_centres_.size() + reference_.size()) * sizeof(double)
         + rotations_.size() * sizeof(Eigen::Quaterniond) + particle_offsets_.size() * sizeof(int)
         + slot_start_.size() * sizeof(std::ptrdiff_t)
         + slot_stride_.size() * sizeof(std::ptrdiff_t)
         + static_cast<std::size_t>(inverse_count_.size()) * sizeof(double);
}

}  // namespace softbench::shape_matching
