// SPDX-License-Identifier: MIT
// Per-cluster shape matching (Mueller et al. 2005, sections 3-4 and the quadratic extension of
// 4.2): the rest-shape precomputation and the allocation-free per-step kernel.
#include "models/shape_matching/cluster_matching.h"

#include "models/double_lanes.h"
#include "models/shape_matching/rotation_extraction.h"
#include "models/team_loop.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace softbench::shape_matching {
namespace {

/// Eigenvalues of the scaled moment matrix Aqq below this fraction of the largest are treated
/// as zero in its pseudo-inverse: the basis is O(1) after scaling, so only directions a flat or
/// tiny cluster does not span (exact zeros up to round-off) fall under it.
constexpr double kPseudoInverseCutoff = 1e-9;

/// With preserve_volume: A / cbrt(det A) only while det A exceeds this (the cluster keeps more
/// than 5% of its volume); below, the cluster follows R alone, since A / cbrt(det A) grows
/// without bound as det A -> 0 and has no meaning for det A < 0.
constexpr double kMinVolumeRatio = 0.05;

/// Held particles whose linear rest moment about their centre (in the scaled basis, per unit
/// of their weight) stays below this are at one point: 1e-6 of the cluster's RMS radius apart
/// at most, far below any two mesh vertices, far above round-off.
constexpr double kHeldPointCutoff = 1e-12;
/// A direction of the held particles' rest moment below this fraction of its largest is not
/// spanned for the rotation: the rotation about an axis is determined by the held particles
/// only to round-off divided by this ratio (1e-10 rad), so a nearly collinear held set is
/// treated as a line (a hinge the free members turn) rather than trusted to round-off.
constexpr double kHeldLineCutoff = 1e-6;
/// The most quaternion iterations for the rotation of held particles spanning a plane or more
/// before the SVD takes over: from the last step's rotation a still or smoothly moving held set
/// needs none or one or two.
constexpr int kHeldRotationIterations = 4;

/// The cluster's map T from its deformable fit (3 x D, in the scaled basis: the rigid map of a
/// scaled offset q / s is s R): beta A + (1 - beta) R (linear) or beta A~ + (1 - beta) [R 0 0]
/// (quadratic). With preserve_volume, the linear block A is divided by its volume change det A
/// along the directions the held particles leave free (`held_span` projects onto what they
/// span; `held_rank` its dimension, 0 for a free cluster): A / cbrt(det A) with none held, the
/// two directions across a held line, the one across a held plane, none when they span the
/// space, so that the map still reproduces the held particles. A quadratic fit's quadratic
/// columns are left as they are: they bend and twist, and their volume change averages out over
/// the cluster.
template <int D>
Eigen::Matrix<double, 3, D> blend_fit(const Eigen::Matrix<double, 3, D>& fit,
                                      const Eigen::Matrix3d& r,
                                      double scale,
                                      const ShapeMatchingParams& params,
                                      int held_rank,
                                      const Eigen::Matrix3d& held_span) {
  Eigen::Matrix<double, 3, D> t = Eigen::Matrix<double, 3, D>::Zero();
  const double beta = params.beta;
  const double det = (fit.template leftCols<3>() / scale).determinant();
  // The free directions are stretched by det^(-1 / free): no more than a free cluster's are at
  // kMinVolumeRatio (2.7x), or the few free directions of a held cluster would carry its goals
  // far away (20x across a held plane at det 0.05).
  const int free = 3 - std::min(held_rank, 3);
  const double min_det = free == 3   ? kMinVolumeRatio
                         : free == 2 ? std::pow(kMinVolumeRatio, 2.0 / 3.0)
                         : free == 1 ? std::cbrt(kMinVolumeRatio)
                                     : kMinVolumeRatio;
  if (beta == 0.0 || (params.preserve_volume && det <= min_det)) {
    t.template leftCols<3>() = scale * r;
    return t;
  }
  t = beta * fit;
  if (params.preserve_volume && free > 0) {
    const double free_scale = free == 3   ? 1.0 / std::cbrt(det)
                              : free == 2 ? 1.0 / std::sqrt(det)
                                          : 1.0 / det;
    const Eigen::Matrix3d volume =
        held_span + free_scale * (Eigen::Matrix3d::Identity() - held_span);
    t.template leftCols<3>() = (t.template leftCols<3>() * volume).eval();
  }
  t.template leftCols<3>() += ((1.0 - beta) * scale) * r;
  return t;
}

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

/// sum_j p_r[j] b_c[j] for r, c in 0..2: nine dot products in one pass over the rows, each as
/// four partial sums (j mod 4) added pairwise at the end, then the last n mod 4 terms: a fixed
/// summation order, so the result does not depend on alignment or threads. With `sums`, also
/// sum_j p_r[j] (the three rows' totals) in the same pass and order. The nine sums are spelt
/// out in four-lane vectors: GCC otherwise vectorises the loop across the nine accumulators,
/// with shuffles and spills. Weighted: p_r[j] is taken as weights[j] p_r[j] throughout.
template <bool kWeighted = false>
Eigen::Matrix3d moments(const double* px,
                        const double* py,
                        const double* pz,
                        const double* b0,
                        const double* b1,
                        const double* b2,
                        int n,
                        Eigen::Vector3d* sums = nullptr,
                        const double* weights = nullptr) {
  // Twelve named sums, not an array: GCC clears a zero-initialised array of vectors in memory
  // with a `rep stos` (tens of cycles to start: a tenth of this function's time on the liver's
  // clusters of about a hundred members), where named ones start as zeroed registers.
  Quad xu{}, xv{}, xw{}, yu{}, yv{}, yw{}, zu{}, zv{}, zw{};
  Quad x_total{}, y_total{}, z_total{};
  int j = 0;
  for (; j + 4 <= n; j += 4) {
    Quad x = load_quad(px + j);
    Quad y = load_quad(py + j);
    Quad z = load_quad(pz + j);
    if constexpr (kWeighted) {
      const Quad weight = load_quad(weights + j);
      x *= weight;
      y *= weight;
      z *= weight;
    }
    const Quad u = load_quad(b0 + j);
    const Quad v = load_quad(b1 + j);
    const Quad w = load_quad(b2 + j);
    xu += x * u;
    xv += x * v;
    xw += x * w;
    yu += y * u;
    yv += y * v;
    yw += y * w;
    zu += z * u;
    zv += z * v;
    zw += z * w;
    if (sums != nullptr) {
      x_total += x;
      y_total += y;
      z_total += z;
    }
  }
  const auto lanes = [](Quad quad) { return (quad[0] + quad[2]) + (quad[1] + quad[3]); };
  Eigen::Matrix3d result;
  result << lanes(xu), lanes(xv), lanes(xw), lanes(yu), lanes(yv), lanes(yw), lanes(zu), lanes(zv),
      lanes(zw);
  Eigen::Vector3d row_sums(lanes(x_total), lanes(y_total), lanes(z_total));
  for (; j < n; ++j) {  // the last n mod 4 terms
    const Eigen::Vector3d p = Eigen::Vector3d(px[j], py[j], pz[j]) * (kWeighted ? weights[j] : 1.0);
    result.col(0) += p * b0[j];
    result.col(1) += p * b1[j];
    result.col(2) += p * b2[j];
    row_sums += p;
  }
  if (sums != nullptr) {
    *sums = row_sums;
  }
  return result;
}

/// Three coordinate vectors of four members, (x0 x1 x2 x3), (y0 ..), (z0 ..), stored side by
/// side as x0 y0 z0 x1 .. z3 at `out` (12 values).
inline void store_interleaved(double* out, Quad x, Quad y, Quad z) {
  const Quad low = __builtin_shufflevector(x, y, 0, 4, 1, 5);           // x0 y0 x1 y1
  const Quad high = __builtin_shufflevector(x, y, 2, 6, 3, 7);          // x2 y2 x3 y3
  const Quad middle = __builtin_shufflevector(low, high, 3, 4, 5, 5);   // y1 x2 y2 -
  store_quad(out, __builtin_shufflevector(low, z, 0, 1, 4, 2));         // x0 y0 z0 x1
  store_quad(out + 4, __builtin_shufflevector(middle, z, 0, 5, 1, 2));  // y1 z1 x2 y2
  store_quad(out + 8, __builtin_shufflevector(high, z, 6, 2, 3, 7));    // z2 x3 y3 z3
}

/// The goals of n members: out[3 j + r] = centre(r) + sum_d t(r, d) basis[d n + j] for the
/// three coordinates r, in one pass over the basis rows (`out` must not overlap `basis`), each
/// sum in the order of d. Eight members at a time: the 3 D coefficients do not fit in the
/// registers beside the sums, and a coefficient loaded once serves two vectors of members (a
/// loop over four members read 3 D coefficients and D basis vectors a step, and the loads
/// bounded it). A pass a coordinate, with its D coefficients in registers, took 10% more.
template <int D>
void goal_rows(const Eigen::Matrix<double, 3, D>& t,
               const Eigen::Vector3d& centre,
               const double* __restrict basis,
               int n,
               double* __restrict out) {
  Quad tx[D];
  Quad ty[D];
  Quad tz[D];
  for (int d = 0; d < D; ++d) {
    tx[d] = broadcast_quad(t(0, d));
    ty[d] = broadcast_quad(t(1, d));
    tz[d] = broadcast_quad(t(2, d));
  }
  const Quad cx = broadcast_quad(centre.x());
  const Quad cy = broadcast_quad(centre.y());
  const Quad cz = broadcast_quad(centre.z());
  int j = 0;
  for (; j + 8 <= n; j += 8) {
    Quad gx0 = cx;
    Quad gy0 = cy;
    Quad gz0 = cz;
    Quad gx1 = cx;
    Quad gy1 = cy;
    Quad gz1 = cz;
    for (int d = 0; d < D; ++d) {
      const Quad b0 = load_quad(basis + d * n + j);
      const Quad b1 = load_quad(basis + d * n + j + 4);
      gx0 += tx[d] * b0;
      gy0 += ty[d] * b0;
      gz0 += tz[d] * b0;
      gx1 += tx[d] * b1;
      gy1 += ty[d] * b1;
      gz1 += tz[d] * b1;
    }
    store_interleaved(out + 3 * j, gx0, gy0, gz0);
    store_interleaved(out + 3 * j + 12, gx1, gy1, gz1);
  }
  for (; j < n; ++j) {
    double gx = cx[0];
    double gy = cy[0];
    double gz = cz[0];
    for (int d = 0; d < D; ++d) {
      const double b = basis[d * n + j];
      gx += tx[d][0] * b;
      gy += ty[d][0] * b;
      gz += tz[d][0] * b;
    }
    out[3 * j] = gx;
    out[3 * j + 1] = gy;
    out[3 * j + 2] = gz;
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

/// The columns of the Cholesky factor of a symmetric positive semi-definite `matrix` with
/// diagonal pivoting (at each step the largest remaining diagonal of the Schur complement),
/// back in the original order, while the pivot stays above kPseudoInverseCutoff of the first:
/// a basis of its range, as many columns as its rank. The pivots fall, so a pivot below the
/// cutoff bounds what is left (Cholesky with complete pivoting reveals the rank).
template <int F>
Eigen::Matrix<double, F, Eigen::Dynamic, 0, F, F> rank_revealing_columns(
    Eigen::Matrix<double, F, F> matrix) {
  Eigen::Matrix<double, F, Eigen::Dynamic, 0, F, F> columns(F, 0);
  int order[F];
  for (int i = 0; i < F; ++i) {
    order[i] = i;
  }
  double first = 0.0;
  for (int k = 0; k < F; ++k) {
    int pivot = k;
    for (int i = k + 1; i < F; ++i) {
      if (matrix(order[i], order[i]) > matrix(order[pivot], order[pivot])) {
        pivot = i;
      }
    }
    std::swap(order[k], order[pivot]);
    const int p = order[k];
    const double value = matrix(p, p);
    if (k == 0) {
      first = value;
    }
    if (!(value > kPseudoInverseCutoff * first)) {
      break;
    }
    Eigen::Matrix<double, F, 1> column = Eigen::Matrix<double, F, 1>::Zero();
    const double root = std::sqrt(value);
    for (int i = k; i < F; ++i) {
      column(order[i]) = matrix(order[i], p) / root;
    }
    for (int i = k + 1; i < F; ++i) {
      for (int j = k + 1; j < F; ++j) {
        matrix(order[i], order[j]) -= column(order[i]) * column(order[j]);
      }
    }
    columns.conservativeResize(Eigen::NoChange, k + 1);
    columns.col(k) = column;
  }
  return columns;
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
  if (member_particle_.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw std::length_error("ClusterMatcher: more than 2^31 memberships");
  }
  slot_membership_.resize(member_particle_.size());
  slot_cluster_.resize(member_particle_.size());
  std::vector<int> next(particle_offsets_.begin(), particle_offsets_.end() - 1);
  for (int k = 0; k < num_clusters(); ++k) {
    for (int m = cluster_begin(k); m < cluster_end(k); ++m) {
      const int slot = next[index(member_particle_[index(m)])]++;
      slot_membership_[index(slot)] = m;
      slot_cluster_[index(slot)] = k;
    }
  }
  inverse_count_.resize(num_particles);
  for (int i = 0; i < num_particles; ++i) {
    const int count = particle_offsets_[index(i) + 1] - particle_offsets_[index(i)];
    assert(count > 0 && "every particle must be in a cluster");
    inverse_count_(i) = 1.0 / count;
  }
  member_inverse_count_.resize(member_particle_.size());
  for (std::size_t m = 0; m < member_particle_.size(); ++m) {
    member_inverse_count_[m] = inverse_count_(member_particle_[m]);
  }
  held_flags_.assign(index(num_particles), 0);
  held_particles_.reserve(index(num_particles));
  held_slot_.assign(index(num_clusters()), -1);
  match_iterations_.assign(index(num_clusters()), 0);
  changed_flags_.assign(index(num_clusters()), 0);
  changed_clusters_.reserve(index(num_clusters()));
  free_held_slots_.reserve(index(num_clusters()));
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
  goals_.assign(3 * memberships + 1, 0.0);
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

ClusterMatcher::Slices ClusterMatcher::slices(int cluster) {
  const int begin = cluster_begin(cluster);
  return {begin,
          cluster_end(cluster) - begin,
          member_particle_.data() + begin,
          member_weight_.data() + begin,
          basis_.data() + static_cast<std::ptrdiff_t>(dim_) * begin,
          work_.data() + 3 * static_cast<std::ptrdiff_t>(begin)};
}

int ClusterMatcher::match_cluster(int cluster, const Eigen::Matrix3Xd& positions) {
  return dim_ == 3 ? match_cluster_with<3>(cluster, positions)
                   : match_cluster_with<9>(cluster, positions);
}

template <int D>
int ClusterMatcher::match_cluster_with(int cluster, const Eigen::Matrix3Xd& positions) {
  [[maybe_unused]] const auto [begin, n, particle, weight, basis, px] = slices(cluster);
  double* py = px + n;
  double* pz = py + n;
  const double* x = positions.data();

  // The mass-weighted offsets m_i (x_i - r) / M from a reference point r near the cluster (its
  // centre of mass of the last match); the centre of mass c = r + their sum, which the moments'
  // first pass adds up. The basis rows have zero weighted mean, so sum m_i (x_i - r) b_i^T =
  // sum m_i (x_i - c) b_i^T: no second pass to subtract c; r only keeps the differences small.
  double* reference = reference_.data() + 3 * index(cluster);
  const double rx = reference[0];
  const double ry = reference[1];
  const double rz = reference[2];
  // Four members at a time: their coordinates gathered into a vector each, then one subtract,
  // multiply and store a coordinate (the scalar loop took three of each a member, and reloaded
  // the weight for each store it could not prove apart from it).
  const Quad rx4 = broadcast_quad(rx);
  const Quad ry4 = broadcast_quad(ry);
  const Quad rz4 = broadcast_quad(rz);
  int j = 0;
  for (; j + 4 <= n; j += 4) {
    const double* a = x + 3 * static_cast<std::ptrdiff_t>(particle[j]);
    const double* b = x + 3 * static_cast<std::ptrdiff_t>(particle[j + 1]);
    const double* c = x + 3 * static_cast<std::ptrdiff_t>(particle[j + 2]);
    const double* d = x + 3 * static_cast<std::ptrdiff_t>(particle[j + 3]);
    const Quad w = load_quad(weight + j);
    store_quad(px + j, w * (Quad{a[0], b[0], c[0], d[0]} - rx4));
    store_quad(py + j, w * (Quad{a[1], b[1], c[1], d[1]} - ry4));
    store_quad(pz + j, w * (Quad{a[2], b[2], c[2], d[2]} - rz4));
  }
  for (; j < n; ++j) {
    const double* xi = x + 3 * static_cast<std::ptrdiff_t>(particle[j]);
    const double w = weight[j];
    px[j] = w * (xi[0] - rx);
    py[j] = w * (xi[1] - ry);
    pz[j] = w * (xi[2] - rz);
  }

  // Apq~ = sum m_i p_i b_i^T / M (3 x D), three basis rows at a time; the first pass also sums
  // the offsets (c - r).
  Eigen::Matrix<double, 3, D> apq;
  Eigen::Vector3d shift;
  for (int g = 0; g < D; g += 3) {
    apq.template middleCols<3>(g) = moments(px, py, pz, basis + g * n, basis + (g + 1) * n,
                                            basis + (g + 2) * n, n, g == 0 ? &shift : nullptr);
  }
  const double cx = rx + shift.x();
  const double cy = ry + shift.y();
  const double cz = rz + shift.z();
  reference[0] = cx;
  reference[1] = cy;
  reference[2] = cz;

  if (const int slot = held_slot_[index(cluster)]; slot >= 0) {
    return match_held<D>(cluster, held_pool_[index(slot)], apq, Eigen::Vector3d(rx, ry, rz),
                         Eigen::Vector3d(cx, cy, cz));
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

  // lazyProduct: a coefficient loop; the default product sends 3 x 9 * 9 x 9 to GEMM.
  const Eigen::Matrix<double, 3, D> fit =
      apq.lazyProduct(Eigen::Map<const Eigen::Matrix<double, D, D>>(moment_inverse_.data()
                                                                    + index(cluster) * D * D));
  const Eigen::Matrix<double, 3, D> t =
      blend_fit<D>(fit, r, scale_[index(cluster)], params_, 0, Eigen::Matrix3d::Zero());

  // Goals g_j = T b_j + c.
  goal_rows<D>(t, Eigen::Vector3d(cx, cy, cz), basis, n, goals_.data() + 3 * std::ptrdiff_t{begin});
  return iterations;
}

template <int D>
int ClusterMatcher::match_held(int cluster,
                               HeldCluster& held,
                               const Eigen::Matrix<double, 3, D>& apq,
                               const Eigen::Vector3d& reference,
                               const Eigen::Vector3d& centre) {
  [[maybe_unused]] const auto [begin, n, particle, weight, basis, px] = slices(cluster);
  double* py = px + n;
  double* pz = py + n;

  // The held members' linear moments sum_H m/M (x - r) [1 q]^T, from the weighted offsets of
  // the first pass: their centre of mass, and their Apq about it.
  Eigen::Matrix<double, 3, 4> held_moment = Eigen::Matrix<double, 3, 4>::Zero();
  for (const int j : held.members) {
    const Eigen::Vector3d offset(px[j], py[j], pz[j]);
    held_moment.col(0) += offset;
    held_moment.col(1) += basis[j] * offset;
    held_moment.col(2) += basis[n + j] * offset;
    held_moment.col(3) += basis[2 * n + j] * offset;
  }
  const Eigen::Vector3d held_centre = reference + held_moment.col(0) / held.weight;

  // The rotation: the held members' first, the free members' among what they leave open.
  const Eigen::Vector3d mean_linear = held.mean.template head<3>();
  const Eigen::Matrix3d held_apq =
      held_moment.template rightCols<3>()
      - (held.weight * (held_centre - reference)) * mean_linear.transpose();
  const Eigen::Matrix3d free_apq =
      apq.template leftCols<3>() + (held_centre - centre) * mean_linear.transpose() - held_apq;
  Eigen::Quaterniond& rotation = rotations_[index(cluster)];
  int iterations = 0;
  const Eigen::Vector3d line = held_apq * held.axis;  // rank 1: held_apq = line axis^T
  if (held.rank >= 2) {
    // Warm-started, the iteration stops at once for held particles that stand still or move
    // rigidly and smoothly; a moment too anisotropic for it to converge in a few iterations
    // gets the SVD (both give the polar rotation), as does a held set new to the cluster (the
    // last rotation was not its).
    if (params_.rotation == ShapeMatchingParams::Rotation::kSvd || held.refitted
        || (iterations = extract_rotation(held_apq, rotation, kHeldRotationIterations))
               == kHeldRotationIterations) {
      rotation = Eigen::Quaterniond(polar_rotation_svd(held_apq));
    }
  } else if (held.rank == 1 && line.norm() > kHeldLineCutoff * held_apq.norm()
             && line.allFinite()) {
    // A hinge: R axis = the line's current direction u, and about u the angle that maximises
    // tr(R^T A_F): for R = Rot(u, theta) R_a, tr(R^T A_F) = const + cos theta (tr M - u.M u)
    // + sin theta u.(M_32 - M_23, M_13 - M_31, M_21 - M_12) with M = A_F R_a^T. R_a is the last
    // rotation turned the shortest way onto the line, so an undetermined angle keeps it.
    const Eigen::Vector3d u = line.normalized();
    const Eigen::Quaterniond aligned =
        (Eigen::Quaterniond::FromTwoVectors(rotation * held.axis, u) * rotation).normalized();
    const Eigen::Matrix3d m = free_apq * aligned.toRotationMatrix().transpose();
    const double cosine = m.trace() - u.dot(m * u);
    const double sine =
        u.dot(Eigen::Vector3d(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1)));
    const double angle = std::hypot(cosine, sine) > kHeldLineCutoff * kHeldLineCutoff * apq.norm()
                             ? std::atan2(sine, cosine)
                             : 0.0;
    rotation = (Eigen::Quaterniond(Eigen::AngleAxisd(angle, u)) * aligned).normalized();
  } else if (params_.rotation == ShapeMatchingParams::Rotation::kSvd) {
    // One held point (or a line collapsed onto one): the free members turn about it.
    rotation = Eigen::Quaterniond(polar_rotation_svd(free_apq));
  } else {
    iterations = extract_rotation(free_apq, rotation, params_.rotation_iterations);
  }
  const Eigen::Matrix3d r = rotation.toRotationMatrix();
  const double scale = scale_[index(cluster)];

  // The deformable fit, anchored: the rigid placement the held particles give (c_H, R) plus
  // the free fit's deviation from it, projected to vanish at the held members:
  // [sR 0] + columns 1..D of (T_0 - Rig) P, Rig = [c_H - r - sR q_H, sR 0].
  const Eigen::Matrix<double, D, D> moment_inverse = Eigen::Map<const Eigen::Matrix<double, D, D>>(
      moment_inverse_.data() + index(cluster) * D * D);
  Eigen::Matrix<double, 3, D> rigid = Eigen::Matrix<double, 3, D>::Zero();
  rigid.template leftCols<3>() = scale * r;
  const Eigen::Matrix<double, 3, D> deviation = apq.lazyProduct(moment_inverse) - rigid;
  const Eigen::Vector3d offset = centre - held_centre + scale * (r * mean_linear);
  const Eigen::Matrix<double, 3, D> fit =
      rigid + offset * held.keep.template block<1, D>(0, 0)
      + deviation.lazyProduct(held.keep.template block<D, D>(1, 0));

  // The pulls' net force and first moment (held_pull()): with s_j = w_j / n_j the members'
  // shares and u_j = q_j - q_H, f = sum s_j (g_j - x_j) and B = sum s_j (g_j - x_j) u_j^T. The
  // goals' part is rest sums times T (g_j = g_0 + T b_j), and s_j (x_j - r) = p_j / n_j for the
  // weighted offsets p_j in the work rows: one more moments pass.
  Eigen::Vector3d offsets;  // sum p_j / n_j
  const double* counts = member_inverse_count_.data() + begin;
  const Eigen::Matrix3d offset_moment =
      moments<true>(px, py, pz, basis, basis + n, basis + 2 * static_cast<std::ptrdiff_t>(n), n,
                    &offsets, counts);  // sum p_j q_j^T / n_j

  // T as for a free cluster, about the held centre: g = c_H + T (b - b_H), keeping the volume
  // only in the directions the held particles leave free.
  const Eigen::Matrix<double, 3, D> t = blend_fit<D>(fit, r, scale, params_, held.rank, held.span);
  const Eigen::Vector3d goal_centre = held_centre - t * held.mean.template head<D>();
  goal_rows<D>(t, goal_centre, basis, n, goals_.data() + 3 * std::ptrdiff_t{begin});

  const Eigen::Vector3d from_reference = goal_centre - reference;
  const Eigen::Vector3d f =
      held.share_total * from_reference + t * held.share_basis.template head<D>() - offsets;
  const Eigen::Matrix3d moment = from_reference * held.share_offset.transpose()
                                 + t * held.share_moment.template topRows<D>()
                                 - (offset_moment - offsets * mean_linear.transpose());
  held.refitted = false;
  held.pull = f / held.weight;
  held.pull_moment = moment * held.spread_inverse;
  return iterations;
}

template <int D>
void ClusterMatcher::refit_held_with(int cluster, HeldCluster& held) {
  constexpr int F = D + 1;
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxFit, kMaxFit>;
  using Range = Eigen::Matrix<double, F, Eigen::Dynamic, 0, F, kMaxFit>;
  [[maybe_unused]] const auto [begin, n, particle, weight, basis, work] = slices(cluster);
  // Captured by name: clang before 16 cannot capture a structured binding.
  const auto basis_of = [basis = basis, n = n](int j) {
    Eigen::Matrix<double, D, 1> b;
    for (int d = 0; d < D; ++d) {
      b(d) = basis[d * n + j];
    }
    return b;
  };

  held.refitted = true;
  held.members.clear();
  held.weight = 0.0;
  Eigen::Matrix<double, D, 1> mean = Eigen::Matrix<double, D, 1>::Zero();
  for (int j = 0; j < n; ++j) {
    if (held_flags_[index(particle[j])] != 0) {
      held.members.push_back(j);  // within the capacity reserved when the entry was made
      held.weight += weight[j];
      mean += weight[j] * basis_of(j);
    }
  }
  assert(!held.members.empty());
  mean /= held.weight;
  held.mean.setZero();
  held.mean.template head<D>() = mean;

  // Their linear rest moment about their centre: its rank decides the rotation, its
  // pseudo-inverse shares the pulls.
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (const int j : held.members) {
    const Eigen::Vector3d q = basis_of(j).template head<3>() - mean.template head<3>();
    spread += weight[j] * q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spread_eigen;
  spread_eigen.computeDirect(spread);  // closed form: ample for ranks at 1e-6 of the largest
  const Eigen::Vector3d& spread_values = spread_eigen.eigenvalues();  // increasing
  held.rank = 0;
  held.spread_inverse.setZero();
  held.span.setZero();
  held.axis = spread_eigen.eigenvectors().col(2);
  if (spread_values(2) > kHeldPointCutoff * held.weight) {
    for (int e = 2; e >= 0 && spread_values(e) > kHeldLineCutoff * spread_values(2); --e) {
      ++held.rank;
      const Eigen::Vector3d v = spread_eigen.eigenvectors().col(e);
      held.spread_inverse += v * v.transpose() / spread_values(e);
      held.span += v * v.transpose();
    }
  }

  // The pulls' rest sums over every member (the class's HeldCluster).
  const double* counts = member_inverse_count_.data() + begin;
  held.share_total = 0.0;
  held.share_offset.setZero();
  held.share_basis.setZero();
  held.share_moment.setZero();
  for (int j = 0; j < n; ++j) {
    const double share = weight[j] * counts[j];
    const Eigen::Matrix<double, D, 1> b = basis_of(j);
    const Eigen::Vector3d u = b.template head<3>() - mean.template head<3>();
    held.share_total += share;
    held.share_offset += share * u;
    held.share_basis.template head<D>() += share * b;
    held.share_moment.template topRows<D>() += share * b * u.transpose();
  }

  // A basis U of the span of the held members' bases [1 b]: the columns of the Cholesky
  // factor of G_H = sum_H m/M [1 b][1 b]^T with diagonal pivoting (rank_revealing_columns()),
  // up to the first pivot below the cutoff of the largest. Smaller ones are dependencies
  // among the held members (more of them than basis functions, or on a plane for the
  // quadratic terms), not constraints.
  Eigen::Matrix<double, F, F> gram = Eigen::Matrix<double, F, F>::Zero();
  for (const int j : held.members) {
    Eigen::Matrix<double, F, 1> b;
    b(0) = 1.0;
    b.template tail<D>() = basis_of(j);
    gram.noalias() += weight[j] * b * b.transpose();
  }
  const Range range = rank_revealing_columns<F>(gram);

  // With G^+ = diag(1, Aqq^+) (the free fit's metric) and M = U^T G^+ U (positive definite: U
  // spans some of the members' bases, where G^+ is), Z = U M^-1 U^T G^+ projects onto
  // the held members' span, orthogonally in that metric, and P = I - Z takes a fit's deviation
  // E to the one nearest it (in the members' weighted goal displacements) that vanishes at
  // every held member: E P, never larger than E, however the held members lie.
  const Eigen::Map<const Eigen::Matrix<double, D, D>> moment_inverse(moment_inverse_.data()
                                                                     + index(cluster) * D * D);
  // lazyProduct throughout: coefficient loops; the default product sends these small
  // dynamic-size blocks to the general matrix product.
  Range metric_range(F, range.cols());  // G^+ U
  metric_range.row(0) = range.row(0);
  metric_range.bottomRows(D) = moment_inverse.lazyProduct(range.bottomRows(D));
  const Small metric = range.transpose().lazyProduct(metric_range);
  const Small solve = metric.ldlt().solve(metric_range.transpose());  // M^-1 U^T G^+
  held.keep.template topLeftCorner<F, D>() =
      -range.lazyProduct(solve.rightCols(D));  // columns 1..D of I - U M^-1 U^T G^+
  held.keep.template block<D, D>(1, 0).diagonal().array() += 1.0;
}

void ClusterMatcher::hold(std::span<const int> particles) {
  const int changed = hold_changes(particles);
  for (int c = 0; c < changed; ++c) {
    refit_held(c);
  }
}

int ClusterMatcher::hold_changes(std::span<const int> particles) {
  // Flags: 1 held by the last call, 2 held by this one; a particle with only one of them
  // changed, and so did each of its clusters' held sets.
  for (const int i : particles) {
    held_flags_[index(i)] |= 2;
  }
  bool any_changed = false;
  const auto mark = [&](int i) {
    any_changed = true;
    for (int s = particle_offsets_[index(i)]; s < particle_offsets_[index(i) + 1]; ++s) {
      changed_flags_[index(slot_cluster_[index(s)])] = 1;
    }
  };
  for (const int i : held_particles_) {
    if (held_flags_[index(i)] == 1) {
      mark(i);  // released
    }
  }
  for (const int i : particles) {
    if (held_flags_[index(i)] == 2) {
      mark(i);  // newly held
    }
  }
  for (const int i : held_particles_) {
    held_flags_[index(i)] &= 2;
  }
  for (const int i : particles) {
    held_flags_[index(i)] = 1;
  }
  held_particles_.assign(particles.begin(), particles.end());  // within the reserved capacity

  changed_clusters_.clear();
  if (!any_changed) {
    return 0;
  }
  // In cluster order, so that the pool entries are handed out the same way on every run.
  for (int k = 0; k < num_clusters(); ++k) {
    if (changed_flags_[index(k)] == 0) {
      continue;
    }
    changed_flags_[index(k)] = 0;
    bool holds = false;
    for (int m = cluster_begin(k); m < cluster_end(k) && !holds; ++m) {
      holds = held_flags_[index(member_particle_[index(m)])] != 0;
    }
    int& slot = held_slot_[index(k)];
    if (!holds) {
      if (slot >= 0) {
        free_held_slots_.push_back(slot);
        slot = -1;
      }
      continue;
    }
    if (slot < 0) {
      if (free_held_slots_.empty()) {
        slot = static_cast<int>(held_pool_.size());
        held_pool_.emplace_back();
      } else {
        slot = free_held_slots_.back();
        free_held_slots_.pop_back();
      }
      held_pool_[index(slot)].members.reserve(index(cluster_end(k) - cluster_begin(k)));
    }
    changed_clusters_.push_back(k);
  }
  return static_cast<int>(changed_clusters_.size());
}

void ClusterMatcher::refit_held(int index_in_changed) {
  const int cluster = changed_clusters_[index(index_in_changed)];
  HeldCluster& held = held_pool_[index(held_slot_[index(cluster)])];
  if (dim_ == 3) {
    refit_held_with<3>(cluster, held);
  } else {
    refit_held_with<9>(cluster, held);
  }
}

Eigen::Vector3d ClusterMatcher::held_pull(int particle) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int s = particle_offsets_[index(particle)]; s < particle_offsets_[index(particle) + 1];
       ++s) {
    const int cluster = slot_cluster_[index(s)];
    const int slot = held_slot_[index(cluster)];
    if (slot < 0) {
      continue;  // not held: no cluster of it has held data
    }
    const HeldCluster& held = held_pool_[index(slot)];
    const int begin = cluster_begin(cluster);
    const int size = cluster_end(cluster) - begin;
    const int j = slot_membership_[index(s)] - begin;
    const double* b = basis_.data() + static_cast<std::ptrdiff_t>(dim_) * begin + j;
    const Eigen::Vector3d q(b[0], b[size], b[2 * static_cast<std::ptrdiff_t>(size)]);
    sum += held.pull + held.pull_moment * (q - held.mean.head<3>());
  }
  return sum;
}

int ClusterMatcher::cluster_of_membership(int membership) const {
  return static_cast<int>(
             std::upper_bound(cluster_offsets_.begin(), cluster_offsets_.end(), membership)
             - cluster_offsets_.begin())
         - 1;
}

Eigen::Vector3d ClusterMatcher::membership_goal(int membership) const {
  const double* g = goals_.data() + 3 * static_cast<std::ptrdiff_t>(membership);
  return {g[0], g[1], g[2]};
}

int ClusterMatcher::match(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd& goals) {
  const int clusters = num_clusters();
  const int particles = num_particles();
  goals.resize(3, particles);
  const bool parallel = worth_parallel();
  maybe_parallel(parallel, [&] {
    team_loop(parallel, clusters,
              [&](int k) { match_iterations_[index(k)] = match_cluster(k, positions); });
    team_blocks(parallel, particles, kParticleChunk, [&](int first, int last) {
      for (int i = first; i < last; ++i) {
        goals.col(i) = goal(i);
      }
    });
  });
  return clusters > 0 ? *std::max_element(match_iterations_.begin(), match_iterations_.end()) : 0;
}

void ClusterMatcher::reset() {
  std::fill(rotations_.begin(), rotations_.end(), Eigen::Quaterniond::Identity());
  reference_ = rest_centres_;
  for (const int i : held_particles_) {
    held_flags_[index(i)] = 0;
  }
  held_particles_.clear();
  changed_clusters_.clear();
  for (int& slot : held_slot_) {
    if (slot >= 0) {
      free_held_slots_.push_back(slot);
      slot = -1;
    }
  }
  // The same order of free entries as a fresh matcher would hand out is not needed: an entry's
  // data is all recomputed when it is handed out.
}

std::size_t ClusterMatcher::held_bytes() const {
  std::size_t bytes = held_flags_.capacity() + changed_flags_.capacity()
                      + (held_particles_.capacity() + held_slot_.capacity()
                         + free_held_slots_.capacity() + changed_clusters_.capacity())
                            * sizeof(int)
                      + held_pool_.capacity() * sizeof(HeldCluster);
  for (const HeldCluster& held : held_pool_) {
    bytes += held.members.capacity() * sizeof(int);
  }
  return bytes;
}

std::size_t ClusterMatcher::memory_bytes() const {
  return member_particle_.size() * sizeof(int)
         + (member_weight_.size() + member_inverse_count_.size()) * sizeof(double)
         + (basis_.size() + work_.size() + goals_.size()) * sizeof(double)
         + (cluster_offsets_.size() + match_iterations_.size()) * sizeof(int)
         + scale_.size() * sizeof(double) + moment_inverse_.size() * sizeof(double)
         + (rest_centres_.size() + reference_.size()) * sizeof(double)
         + rotations_.size() * sizeof(Eigen::Quaterniond) + particle_offsets_.size() * sizeof(int)
         + (slot_membership_.size() + slot_cluster_.size()) * sizeof(int)
         + static_cast<std::size_t>(inverse_count_.size()) * sizeof(double) + held_bytes();
}

}  // namespace softbench::shape_matching
