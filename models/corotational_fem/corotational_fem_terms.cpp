// SPDX-License-Identifier: MIT
// The corotational FEM's element terms (a step's second phase): per element, the right-hand side
// part of its four nodes and the rotated, volume-scaled gradients w_a the gathers read. The
// elastic forces are f_a = -V R sigma(sym(R^T F) - I) b_a (b_a the shape gradients, the rows of
// Dm^-1 for a = 1..3 and b_0 = -(b_1 + b_2 + b_3)): with R the polar rotation of F, minus the
// gradient of tet_element.h's element_energy (the dR terms vanish: R^T F is symmetric and
// dR = R W with W skew); with R = I, linear FEM's f = -K (x - X).
#include "models/corotational_fem/corotational_fem_model.h"

#include <algorithm>
#include <cstddef>

namespace softbench::corotational_fem {
namespace {

/// Elements computed side by side, one per vector lane. The terms are a dozen small matrix
/// products per element; written element by element (Eigen's fixed 3x3 products) they ran one
/// scalar multiply-add at a time, 15-18% of the liver's step. In lanes, structure of arrays,
/// every multiply-add is a full vector's. Eight lanes: two AVX2 vectors of doubles (or four
/// SSE2 ones), and the batch's arrays (about 100 doubles a lane) stay in L1.
constexpr int kLanes = 8;

/// Column-major 3x3 entries of each lane: m[i + 3 j][lane] is entry (i, j).
using Lanes3x3 = double[9][kLanes];

/// out = a^T b or a b (transpose_a), lane by lane.
template <bool kTransposeA>
[[gnu::always_inline]] inline void multiply(const Lanes3x3& a, const Lanes3x3& b, Lanes3x3& out) {
#pragma omp simd
  for (int lane = 0; lane < kLanes; ++lane) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        const auto at = [&](int r, int c) {
          return kTransposeA ? a[c + 3 * r][lane] : a[r + 3 * c][lane];
        };
        out[i + 3 * j][lane] = (at(i, 0) * b[0 + 3 * j][lane] + at(i, 1) * b[1 + 3 * j][lane])
                               + at(i, 2) * b[2 + 3 * j][lane];
      }
    }
  }
}

/// out = a b^T, lane by lane.
[[gnu::always_inline]] inline void multiply_transposed(const Lanes3x3& a,
                                                       const Lanes3x3& b,
                                                       Lanes3x3& out) {
#pragma omp simd
  for (int lane = 0; lane < kLanes; ++lane) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        out[i + 3 * j][lane] = (a[i][lane] * b[j][lane] + a[i + 3][lane] * b[j + 3][lane])
                               + a[i + 6][lane] * b[j + 6][lane];
      }
    }
  }
}

/// Copies `count` 3x3 matrices (column-major, Eigen's layout) into lanes; unused lanes get 0.
[[gnu::always_inline]] inline void load(const Eigen::Matrix3d* matrices, int count, Lanes3x3& out) {
  for (int lane = 0; lane < kLanes; ++lane) {
    for (int k = 0; k < 9; ++k) {
      out[k][lane] = lane < count ? matrices[lane].data()[k] : 0.0;
    }
  }
}

/// A lane's four node columns from its last three, h_1..h_3 (the columns of `h`): scale h_a,
/// and node 0 minus their sum (the four sum to zero, as b_0 = -(b_1 + b_2 + b_3)).
[[gnu::always_inline]] inline void store_nodes(const Lanes3x3& h,
                                               int lane,
                                               double scale,
                                               Matrix34d& out) {
  for (int i = 0; i < 3; ++i) {
    const double h1 = h[i][lane];
    const double h2 = h[i + 3][lane];
    const double h3 = h[i + 6][lane];
    out(i, 0) = -scale * ((h1 + h2) + h3);
    out(i, 1) = scale * h1;
    out(i, 2) = scale * h2;
    out(i, 3) = scale * h3;
  }
}

}  // namespace

void CorotationalFemModel::compute_element_terms(double velocity_weight, double force_scale) {
  const bool corotational =
      params_.formulation == CorotationalFemParams::Formulation::kCorotational;
  const double two_mu = 2.0 * lame_.mu;
  const double lambda = lame_.lambda;
  const int num_batches = (num_elements_ + kLanes - 1) / kLanes;
#pragma omp parallel for schedule(static) if (num_elements_ > kParallelElements)
  for (int batch = 0; batch < num_batches; ++batch) {
    const int first = batch * kLanes;
    const int count = std::min(kLanes, num_elements_ - first);
    const auto begin = static_cast<std::size_t>(first);
    alignas(64) Lanes3x3 rotation;
    alignas(64) Lanes3x3 deformation;
    alignas(64) Lanes3x3 rest_inverse;
    alignas(64) Lanes3x3 work;
    alignas(64) Lanes3x3 product;
    alignas(64) double volume[kLanes];
    load(rotations_.data() + begin, count, rotation);
    load(deformations_.data() + begin, count, deformation);
    for (int lane = 0; lane < kLanes; ++lane) {
      const TetRest* rest =
          lane < count ? &elements_[begin + static_cast<std::size_t>(lane)] : nullptr;
      for (int k = 0; k < 9; ++k) {
        rest_inverse[k][lane] = rest != nullptr ? rest->rest_inverse.data()[k] : 0.0;
      }
      volume[lane] = rest != nullptr ? rest->volume : 0.0;
    }
    if (velocity_weight != 0.0) {
      // F + (beta + dt) G, G = [v1 - v0, v2 - v0, v3 - v0] Dm^-1 the velocity gradient: folds
      // -dt (beta + dt) K v into the force.
      for (int lane = 0; lane < kLanes; ++lane) {
        for (int c = 0; c < 3; ++c) {
          for (int i = 0; i < 3; ++i) {
            work[i + 3 * c][lane] = lane < count ? velocities_(i, tets_(c + 1, first + lane))
                                                       - velocities_(i, tets_(0, first + lane))
                                                 : 0.0;
          }
        }
      }
      multiply<false>(work, rest_inverse, product);
#pragma omp simd
      for (int lane = 0; lane < kLanes; ++lane) {
        for (int k = 0; k < 9; ++k) {
          deformation[k][lane] += velocity_weight * product[k][lane];
        }
      }
    }
    // The stress sigma(sym(R^T F) - I) (into work), R sigma (product), and its nodal forces
    // -V R sigma b_a, b_1..3 the rows of Dm^-1 (work).
    multiply<true>(rotation, deformation, product);
#pragma omp simd
    for (int lane = 0; lane < kLanes; ++lane) {
      const double trace =
          (product[0][lane] - 1.0) + (product[4][lane] - 1.0) + (product[8][lane] - 1.0);
      for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) {
          const double strain =
              0.5 * (product[i + 3 * j][lane] + product[j + 3 * i][lane]) - (i == j ? 1.0 : 0.0);
          work[i + 3 * j][lane] = two_mu * strain + (i == j ? lambda * trace : 0.0);
        }
      }
    }
    multiply<false>(rotation, work, product);
#pragma omp simd
    for (int lane = 0; lane < kLanes; ++lane) {
      for (int k = 0; k < 9; ++k) {
        product[k][lane] *= volume[lane];
      }
    }
    multiply_transposed(product, rest_inverse, work);
    for (int lane = 0; lane < count; ++lane) {
      store_nodes(work, lane, -force_scale, element_rhs_[begin + static_cast<std::size_t>(lane)]);
    }
    if (!corotational) {
      continue;  // w_a stays sqrt(V) b_a (reset())
    }
    load(scaled_gradients_.data() + begin, count, work);
    multiply<false>(rotation, work, product);
    for (int lane = 0; lane < count; ++lane) {
      store_nodes(product, lane, 1.0, element_gradients_[begin + static_cast<std::size_t>(lane)]);
    }
  }
}

}  // namespace softbench::corotational_fem
