// SPDX-License-Identifier: MIT
// The corotational FEM's element kernels, a batch of elements side by side: F and R (a step's
// first phase), then per element the right-hand side part of its four nodes and the rotated,
// volume-scaled gradients w_a the gathers read. The elastic forces are
// f_a = -V R sigma(sym(R^T F) - I) b_a (b_a the shape gradients, the rows of Dm^-1 for a = 1..3
// and b_0 = -(b_1 + b_2 + b_3)): with R the polar rotation of F, minus the gradient of
// tet_element.h's element_energy (the dR terms vanish: R^T F is symmetric and dR = R W with W
// skew); with R = I, linear FEM's f = -K (x - X).
#include "models/corotational_fem/corotational_fem_model.h"
#include "models/corotational_fem/polar_decomposition.h"

#include <algorithm>
#include <cstddef>
#include <span>

namespace softbench::corotational_fem {
namespace {

/// Elements computed side by side, one per vector lane (kElementLanes). The terms are a dozen small
/// matrix products per element; written element by element (Eigen's fixed 3x3 products) they ran
/// one scalar multiply-add at a time, 15-18% of the liver's step. In lanes, structure of arrays,
/// every multiply-add is a full vector's. Eight lanes: two AVX2 vectors of doubles (or four
/// SSE2 ones), and the batch's arrays (about 100 doubles a lane) stay in L1.
constexpr int kLanes = CorotationalFemModel::kElementLanes;
static_assert(kLanes == kRotationLanes, "the rotations are extracted in the terms' lanes");
using Lanes3x3 = CorotationalFemModel::Lanes3x3;

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
    CorotationalFemModel::set_lane(out, lane,
                                   lane < count ? matrices[lane] : Eigen::Matrix3d::Zero().eval());
  }
}

/// The first `count` lanes into 3x3 matrices.
[[gnu::always_inline]] inline void store(const Lanes3x3& lanes, int count, Eigen::Matrix3d* out) {
  for (int lane = 0; lane < count; ++lane) {
    out[lane] = CorotationalFemModel::lane_of(lanes, lane);
  }
}

/// [y1 - y0, y2 - y0, y3 - y0] of each element's nodes (the columns of `nodal`, e.g. positions
/// or velocities) into lanes: element first + lane for lanes below `count`, zeros after.
[[gnu::always_inline]] inline void load_edges(const Eigen::Matrix3Xd& nodal,
                                              const Eigen::Matrix4Xi& tets,
                                              int first,
                                              int count,
                                              Lanes3x3& out) {
  for (int lane = 0; lane < count; ++lane) {
    const double* y0 = nodal.col(tets(0, first + lane)).data();
    for (int c = 0; c < 3; ++c) {
      const double* y = nodal.col(tets(c + 1, first + lane)).data();
      for (int i = 0; i < 3; ++i) {
        out[i + 3 * c][lane] = y[i] - y0[i];
      }
    }
  }
  for (int lane = count; lane < kLanes; ++lane) {
    for (int k = 0; k < 9; ++k) {
      out[k][lane] = 0.0;
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

/// One batch's elements, kLanes of them from `first` (`count` used; the others hold zeros).
struct CorotationalFemModel::ElementBatch {
  int first = 0;
  int count = 0;
  const RestBatch* rest = nullptr;
  alignas(64) Lanes3x3 deformation;  ///< F
  alignas(64) Lanes3x3 rotation;     ///< R
};

template <class Body>
void CorotationalFemModel::for_each_batch(const Body& body) {
  const auto num_batches = static_cast<int>(rest_batches_.size());
#pragma omp parallel for schedule(static) if (threaded())
  for (int batch = 0; batch < num_batches; ++batch) {
    ElementBatch lanes;
    lanes.first = batch * kLanes;
    lanes.count = std::min(kLanes, num_elements_ - lanes.first);
    lanes.rest = &rest_batches_[static_cast<std::size_t>(batch)];
    body(lanes);
  }
}

void CorotationalFemModel::deform(ElementBatch& lanes, bool hold_rotations) {
  const int first = lanes.first;
  const int count = lanes.count;
  const auto begin = static_cast<std::size_t>(first);
  // F = [x1 - x0, x2 - x0, x3 - x0] Dm^-1.
  alignas(64) Lanes3x3 edges;
  load_edges(positions_, tets_, first, count, edges);
  multiply<false>(edges, lanes.rest->rest_inverse, lanes.deformation);
  if (params_.formulation != CorotationalFemParams::Formulation::kCorotational) {
    for (int k = 0; k < 9; ++k) {
      for (int lane = 0; lane < kLanes; ++lane) {
        lanes.rotation[k][lane] = k % 4 == 0 ? 1.0 : 0.0;  // R = I: linear FEM
      }
    }
  } else if (hold_rotations) {
    load(rotations_.data() + begin, count, lanes.rotation);
  } else if (params_.rotation == CorotationalFemParams::Rotation::kSvd) {
    for (int lane = 0; lane < kLanes; ++lane) {
      set_lane(lanes.rotation, lane,
               lane < count ? rotation_by_svd(lane_of(lanes.deformation, lane))
                            : Eigen::Matrix3d::Identity().eval());
    }
  } else {
    // Warm-started from the last rotation of each element.
    extract_rotation_lanes(lanes.deformation,
                           std::span(quaternions_).subspan(begin, static_cast<std::size_t>(count)),
                           lanes.rotation, params_.rotation_iterations, params_.rotation_tolerance);
  }
}

void CorotationalFemModel::make_terms(ElementBatch& lanes, const TermScales& scales) {
  const bool corotational =
      params_.formulation == CorotationalFemParams::Formulation::kCorotational;
  const double two_mu = 2.0 * lame_.mu;
  const double lambda = lame_.lambda;
  const double velocity_weight = scales.velocity_weight;
  const int first = lanes.first;
  const int count = lanes.count;
  const auto begin = static_cast<std::size_t>(first);
  const Lanes3x3& rotation = lanes.rotation;
  const Lanes3x3& rest_inverse = lanes.rest->rest_inverse;
  Lanes3x3& deformation = lanes.deformation;
  alignas(64) Lanes3x3 work;
  alignas(64) Lanes3x3 product;
  if (velocity_weight != 0.0) {
    // F + (beta + dt) G, G = [v1 - v0, v2 - v0, v3 - v0] Dm^-1 the velocity gradient: folds
    // -dt (beta + dt) K v into the force.
    load_edges(velocities_, tets_, first, count, work);
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
      product[k][lane] *= lanes.rest->volume[lane];
    }
  }
  multiply_transposed(product, rest_inverse, work);
  for (int lane = 0; lane < count; ++lane) {
    store_nodes(work, lane, -scales.force_scale,
                element_rhs_[begin + static_cast<std::size_t>(lane)]);
  }
  if (!corotational) {
    return;  // w_a stays sqrt(V) b_a (reset())
  }
  multiply<false>(rotation, lanes.rest->scaled_gradients, product);
  for (int lane = 0; lane < count; ++lane) {
    store_nodes(product, lane, 1.0, element_gradients_[begin + static_cast<std::size_t>(lane)]);
  }
}

void CorotationalFemModel::update_deformations(bool hold_rotations) {
  for_each_batch([&](ElementBatch& lanes) {
    deform(lanes, hold_rotations);
    const auto begin = static_cast<std::size_t>(lanes.first);
    store(lanes.deformation, lanes.count, deformations_.data() + begin);
    store(lanes.rotation, lanes.count, rotations_.data() + begin);
  });
}

void CorotationalFemModel::compute_element_terms(const TermScales& scales) {
  for_each_batch([&](ElementBatch& lanes) {
    const auto begin = static_cast<std::size_t>(lanes.first);
    load(deformations_.data() + begin, lanes.count, lanes.deformation);
    load(rotations_.data() + begin, lanes.count, lanes.rotation);
    make_terms(lanes, scales);
  });
}

void CorotationalFemModel::deform_and_compute_terms(const TermScales& scales) {
  for_each_batch([&](ElementBatch& lanes) {
    deform(lanes, /*hold_rotations=*/false);
    make_terms(lanes, scales);
  });
}

}  // namespace softbench::corotational_fem
