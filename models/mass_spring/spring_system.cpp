// SPDX-License-Identifier: MIT
#include "models/mass_spring/spring_system.h"

#include "models/double_lanes.h"
#include "models/eisenstat_cg.h"
#include "models/warm_start.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace softbench::mass_spring {
namespace {

/// A residual this far below the first leaves nothing to gain (an exact preconditioner gets
/// there before the error estimate has its window).
constexpr double kRoundoff = 1e-14;

using Sym = Eigen::Matrix<double, 6, 1>;  // xx yy zz xy xz yz

Sym to_sym(const Eigen::Matrix3d& m) {
  Sym s;
  s << m(0, 0), m(1, 1), m(2, 2), 0.5 * (m(0, 1) + m(1, 0)), 0.5 * (m(0, 2) + m(2, 0)),
      0.5 * (m(1, 2) + m(2, 1));
  return s;
}

Eigen::Matrix3d from_sym(const double* s) {
  Eigen::Matrix3d m;
  m << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
  return m;
}

/// out = M in for a symmetric M (6 values).
inline void sym_multiply(const double* s, const double* in, double* out) {
  out[0] = s[0] * in[0] + s[3] * in[1] + s[4] * in[2];
  out[1] = s[3] * in[0] + s[1] * in[1] + s[5] * in[2];
  out[2] = s[4] * in[0] + s[5] * in[1] + s[2] * in[2];
}

/// The inverse of a symmetric positive definite 3x3 matrix, by cofactors.
Sym sym_inverse(const Sym& s) {
  const double a = s[0];
  const double b = s[1];
  const double c = s[2];
  const double d = s[3];
  const double e = s[4];
  const double f = s[5];
  const double cxx = b * c - f * f;
  const double cxy = e * f - d * c;
  const double cxz = d * f - b * e;
  const double inverse_determinant = 1.0 / (a * cxx + d * cxy + e * cxz);
  Sym inverse;
  inverse << cxx * inverse_determinant, (a * c - e * e) * inverse_determinant,
      (a * b - d * d) * inverse_determinant, cxy * inverse_determinant, cxz * inverse_determinant,
      (d * e - a * f) * inverse_determinant;
  return inverse;
}

/// The springs' coefficients, by column (SpringSystem::coefficients_).
struct Springs {
  const double* ux;
  const double* uy;
  const double* uz;
  const double* across;

  /// f = B_e r = u (u . r) + across r.
  void apply(Eigen::Index e, const double* r, double* f) const {
    const double along = ux[e] * r[0] + uy[e] * r[1] + uz[e] * r[2];
    f[0] = ux[e] * along + across[e] * r[0];
    f[1] = uy[e] * along + across[e] * r[1];
    f[2] = uz[e] * along + across[e] * r[2];
  }
};

inline double dot3(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Springs springs_of(const Eigen::Matrix<double, Eigen::Dynamic, 4>& coefficients) {
  return {coefficients.col(0).data(), coefficients.col(1).data(), coefficients.col(2).data(),
          coefficients.col(3).data()};
}

}  // namespace

SpringSystem::SpringSystem(int num_vertices, const Eigen::Matrix2Xi& springs)
    : num_vertices_(num_vertices),
      owned_offsets_(static_cast<std::size_t>(num_vertices) + 1, 0),
      others_(static_cast<std::size_t>(springs.cols())),
      other_coordinates_(static_cast<std::size_t>(springs.cols())),
      firsts_(static_cast<std::size_t>(springs.cols())),
      incident_offsets_(static_cast<std::size_t>(num_vertices) + 1, 0),
      coefficients_(springs.cols(), 4),
      masses_(Eigen::VectorXd::Zero(num_vertices)),
      diagonal_(6, num_vertices),
      filtered_(6, num_vertices),
      inverse_(6, num_vertices),
      kinds_(static_cast<std::size_t>(num_vertices), kFree),
      slots_(static_cast<std::size_t>(num_vertices), -1) {
  const Eigen::Index num_springs = springs.cols();
  for (Eigen::Index e = 0; e < num_springs; ++e) {
    const int i = springs(0, e);
    const int j = springs(1, e);
    if (i < 0 || i >= j || j >= num_vertices
        || (e > 0
            && (springs(0, e - 1) > i || (springs(0, e - 1) == i && springs(1, e - 1) >= j)))) {
      throw std::invalid_argument(
          "SpringSystem: springs must be pairs (i, j), i < j, sorted and unique");
    }
    firsts_[static_cast<std::size_t>(e)] = i;
    others_[static_cast<std::size_t>(e)] = j;
    other_coordinates_[static_cast<std::size_t>(e)] = 3 * j;
    ++owned_offsets_[static_cast<std::size_t>(i) + 1];
    ++incident_offsets_[static_cast<std::size_t>(i) + 1];
    ++incident_offsets_[static_cast<std::size_t>(j) + 1];
  }
  for (std::size_t v = 0; v < static_cast<std::size_t>(num_vertices); ++v) {
    owned_offsets_[v + 1] += owned_offsets_[v];
    incident_offsets_[v + 1] += incident_offsets_[v];
  }
  incident_springs_.resize(static_cast<std::size_t>(incident_offsets_.back()));
  std::vector<int> fill(incident_offsets_.begin(), incident_offsets_.end() - 1);
  for (Eigen::Index e = 0; e < num_springs; ++e) {
    for (int end = 0; end < 2; ++end) {
      incident_springs_[static_cast<std::size_t>(
          fill[static_cast<std::size_t>(springs(end, e))]++)] = static_cast<int>(e);
    }
  }
  coefficients_.setZero();
  diagonal_.setZero();
  filtered_.setZero();
  inverse_.setZero();
  const Eigen::Index size = 3 * static_cast<Eigen::Index>(num_vertices);
  for (Eigen::VectorXd* vector : {&rhs_, &known_, &solution_, &residual_, &preconditioned_,
                                  &direction_, &product_, &sweep_, &carry_, &transformed_}) {
    vector->setZero(size);
  }
  for (History* block : {&history_, &basis_, &basis_products_}) {
    block->setZero(3 * kHistory, num_vertices);
  }
}

void SpringSystem::bind(const VertexConstraints& constraints) {
  for (const int v : held_vertices_) {
    kinds_[static_cast<std::size_t>(v)] = kFree;
    slots_[static_cast<std::size_t>(v)] = -1;
  }
  for (const int v : penalty_vertices_) {
    slots_[static_cast<std::size_t>(v)] = -1;
  }
  held_vertices_.clear();
  held_.clear();
  held_filters_.clear();
  penalty_vertices_.clear();
  penalties_.clear();
  for (const int v : constraints.vertices()) {
    const PositionConstraint* constraint = constraints.of(v);
    const auto vertex = static_cast<std::size_t>(v);
    if (is_exact(constraint)) {
      kinds_[vertex] = constraint->slides() ? kSliding : kFixed;
      slots_[vertex] = static_cast<int>(held_vertices_.size());
      held_vertices_.push_back(v);
      held_.push_back(constraint->held);
      Eigen::Matrix3d filter_columns;
      for (int a = 0; a < 3; ++a) {
        filter_columns.col(a) = filter(v, Eigen::Vector3d::Unit(a));
      }
      held_filters_.push_back(filter_columns);
    } else if (is_penalty(constraint)) {
      slots_[vertex] = static_cast<int>(penalty_vertices_.size());
      penalty_vertices_.push_back(v);
      penalties_.push_back(Eigen::Matrix3d::Zero());
    }
  }
}

void SpringSystem::set_vertex(int v, double mass, const Eigen::Matrix3d& penalty) {
  masses_(v) = mass;
  const int slot = slots_[static_cast<std::size_t>(v)];
  if (slot >= 0 && kinds_[static_cast<std::size_t>(v)] == kFree) {  // a penalty vertex
    penalties_[static_cast<std::size_t>(slot)] = penalty;
  }
}

void SpringSystem::prepare() {
  for (int v = 0; v < num_vertices_; ++v) {
    diagonal_.col(v) << masses_(v), masses_(v), masses_(v), 0.0, 0.0, 0.0;
  }
  for (std::size_t k = 0; k < penalty_vertices_.size(); ++k) {
    diagonal_.col(penalty_vertices_[k]) += to_sym(penalties_[k]);
  }
  // Each spring's block onto both its vertices' (one pass over the springs, in order), as three
  // pairs: (xx, yy), (zz, xy), (xz, yz).
  const Springs springs = springs_of(coefficients_);
  double* diagonal = diagonal_.data();
  for (int v = 0; v < num_vertices_; ++v) {
    Pair own[3] = {};
    for (int e = owned_offsets_[static_cast<std::size_t>(v)];
         e < owned_offsets_[static_cast<std::size_t>(v) + 1]; ++e) {
      const double ux = springs.ux[e];
      const double uy = springs.uy[e];
      const double uz = springs.uz[e];
      const double across = springs.across[e];
      const Pair xy = {ux, uy};
      const Pair block[3] = {xy * xy + across, Pair{uz, ux} * Pair{uz, uy} + Pair{across, 0.0},
                             xy * Pair{uz, uz}};
      double* other = diagonal + 6 * others_[static_cast<std::size_t>(e)];
      for (int h = 0; h < 3; ++h) {
        own[h] += block[h];
        store_pair(other + 2 * h, load_pair(other + 2 * h) + block[h]);
      }
    }
    for (int h = 0; h < 3; ++h) {
      store_pair(diagonal + 6 * v + 2 * h, load_pair(diagonal + 6 * v + 2 * h) + own[h]);
    }
  }
  for (int v = 0; v < num_vertices_; ++v) {
    const Sym block = diagonal_.col(v);
    switch (kinds_[static_cast<std::size_t>(v)]) {
      case kFree:
        filtered_.col(v) = block;
        inverse_.col(v) = sym_inverse(block);
        break;
      case kFixed:
        filtered_.col(v).setZero();
        inverse_.col(v).setZero();
        break;
      case kSliding: {
        const Eigen::Matrix3d& held =
            held_[static_cast<std::size_t>(slots_[static_cast<std::size_t>(v)])];
        const Eigen::Matrix3d free = Eigen::Matrix3d::Identity() - held;
        const Eigen::Matrix3d projected = free * from_sym(block.data()) * free;
        filtered_.col(v) = to_sym(projected);
        // (S D S)^+ = (S D S + H)^-1 - H: S D S + H is invertible and keeps both subspaces.
        inverse_.col(v) = to_sym(Eigen::Matrix3d((projected + held).inverse() - held));
        break;
      }
    }
  }
}

Eigen::Matrix3d SpringSystem::spring_block(Eigen::Index e) const {
  const Eigen::Vector3d u = coefficients_.row(e).head<3>().transpose();
  return u * u.transpose() + coefficients_(e, 3) * Eigen::Matrix3d::Identity();
}

Eigen::Matrix3d SpringSystem::vertex_block(int v) const {
  return from_sym(diagonal_.col(v).data());
}

Eigen::Vector3d SpringSystem::filter(int v, const Eigen::Vector3d& value) const {
  switch (kinds_[static_cast<std::size_t>(v)]) {
    case kFree:
      return value;
    case kFixed:
      return Eigen::Vector3d::Zero();
    case kSliding:
      break;
  }
  const Eigen::Matrix3d& held =
      held_[static_cast<std::size_t>(slots_[static_cast<std::size_t>(v)])];
  return value - held * value;
}

Eigen::Vector3d SpringSystem::row(int v, const Eigen::VectorXd& x) const {
  Eigen::Vector3d result = masses_(v) * x.segment<3>(3 * v);
  const int slot = slots_[static_cast<std::size_t>(v)];
  if (slot >= 0 && kinds_[static_cast<std::size_t>(v)] == kFree) {
    result += penalties_[static_cast<std::size_t>(slot)] * x.segment<3>(3 * v);
  }
  for (int k = incident_begin(v); k < incident_end(v); ++k) {
    const int e = incident_springs_[static_cast<std::size_t>(k)];
    const int other =
        firsts_[static_cast<std::size_t>(e)] + others_[static_cast<std::size_t>(e)] - v;
    const Eigen::Vector3d r = x.segment<3>(3 * v) - x.segment<3>(3 * other);
    Eigen::Vector3d f;
    springs_of(coefficients_).apply(e, r.data(), f.data());
    result += f;
  }
  return result;
}

double SpringSystem::energy(const double* y) const {
  double sum = 0.0;
  for (int v = 0; v < num_vertices_; ++v) {
    sum += masses_(v) * dot3(y + 3 * v, y + 3 * v);
  }
  for (std::size_t k = 0; k < penalty_vertices_.size(); ++k) {
    const Eigen::Map<const Eigen::Vector3d> yv(y + 3 * penalty_vertices_[k]);
    sum += yv.dot(penalties_[k] * yv);
  }
  const Springs springs = springs_of(coefficients_);
  for (std::size_t e = 0; e < others_.size(); ++e) {
    const double* yi = y + 3 * firsts_[e];
    const double* yj = y + 3 * others_[e];
    const double r[3] = {yi[0] - yj[0], yi[1] - yj[1], yi[2] - yj[2]};
    const double along = springs.ux[e] * r[0] + springs.uy[e] * r[1] + springs.uz[e] * r[2];
    sum += along * along + springs.across[e] * dot3(r, r);
  }
  return sum;
}

SolveReport SpringSystem::solve(const Eigen::VectorXd& b,
                                const Eigen::Matrix3Xd& known,
                                Eigen::VectorXd& x,
                                const Eigen::Matrix3Xd& offset,
                                Preconditioner preconditioner,
                                double tolerance,
                                int max_iterations) {
  // u_k, and S (b - A u_k): A u_k from the springs at held vertices only.
  known_.setZero();
  for (std::size_t k = 0; k < held_vertices_.size(); ++k) {
    const int c = held_vertices_[k];
    known_.segment<3>(3 * c) = held_[k] * known.col(c);
  }
  rhs_ = b;
  const Springs springs = springs_of(coefficients_);
  for (const int c : held_vertices_) {
    rhs_.segment<3>(3 * c) -= masses_(c) * known_.segment<3>(3 * c);
  }
  for_each_held_spring([&](Eigen::Index e, int i, int j) {
    const Eigen::Vector3d r = known_.segment<3>(3 * i) - known_.segment<3>(3 * j);
    Eigen::Vector3d f;
    springs.apply(e, r.data(), f.data());
    rhs_.segment<3>(3 * i) -= f;
    rhs_.segment<3>(3 * j) += f;
  });
  for (const int c : held_vertices_) {
    rhs_.segment<3>(3 * c) = filter(c, rhs_.segment<3>(3 * c));
  }

  SolveReport report;
  const double rhs_norm = std::sqrt(rhs_.squaredNorm() + known_.squaredNorm());
  if (rhs_norm == 0.0) {
    x.setZero();
    return report;
  }
  // w0, and the energy the error is measured against: |S (v + x0)|^2_A + |H v + u_k|^2.
  warm_start();
  for (int v = 0; v < num_vertices_; ++v) {
    product_.segment<3>(3 * v) =
        solution_.segment<3>(3 * v)
        + (kinds_[static_cast<std::size_t>(v)] == kFree ? Eigen::Vector3d(offset.col(v))
                                                        : filter(v, offset.col(v)));
  }
  double reference_energy = energy(product_.data());
  for (std::size_t k = 0; k < held_vertices_.size(); ++k) {
    const int c = held_vertices_[k];
    reference_energy += (held_[k] * offset.col(c) + known_.segment<3>(3 * c)).squaredNorm();
  }

  reference_energy = std::max(reference_energy, energy_floor_);
  report = preconditioner == Preconditioner::kSsor
               ? solve_ssor(tolerance, max_iterations, reference_energy)
               : solve_block_jacobi(tolerance, max_iterations, reference_energy);
  report.residual /= rhs_norm;
  x = known_ + solution_;
  report.succeeded = std::isfinite(report.residual) && x.allFinite();
  if (report.succeeded) {
    history_head_ = (history_head_ + 1) % kHistory;
    for (int v = 0; v < num_vertices_; ++v) {
      for (int a = 0; a < 3; ++a) {
        history_(kHistory * a + history_head_, v) = x(3 * v + a);
      }
    }
    history_count_ = std::min(history_count_ + 1, kHistory);
  } else {
    forget_solutions();
  }
  return report;
}

void SpringSystem::forget_solutions() {
  history_.setZero();  // the unused slots' zero products keep them out of the combination
  history_count_ = 0;
}

void SpringSystem::warm_start() {
  using Small = Eigen::Matrix<double, kHistory, kHistory>;
  using SmallVector = Eigen::Matrix<double, kHistory, 1>;
  solution_.setZero();
  residual_ = rhs_;
  if (history_count_ == 0) {
    return;
  }
  basis_ = history_;
  for (const int c : held_vertices_) {
    for (int k = 0; k < kHistory; ++k) {
      Eigen::Map<Eigen::Vector3d, 0, Eigen::InnerStride<kHistory>> value(&basis_(k, c));
      value = filter(c, value);
    }
  }
  multiply_history();
  // G_ij = s_i . S A S s_j and h_i = s_i . S (b - A u_k), over every vertex and coordinate. A
  // slot not yet used holds zeros: its row and column of G are zero, so is its coefficient.
  Small gram = Small::Zero();
  SmallVector projected = SmallVector::Zero();
  for (int v = 0; v < num_vertices_; ++v) {
    for (int a = 0; a < 3; ++a) {
      const auto basis = basis_.col(v).segment<kHistory>(kHistory * a);
      const auto product = basis_products_.col(v).segment<kHistory>(kHistory * a);
      gram.noalias() += basis * product.transpose();
      projected += rhs_(3 * v + a) * basis;
    }
  }
  // The past solutions are often nearly parallel: GalerkinWarmStart's pseudo-inverse. The
  // products are symmetric up to round-off.
  static_assert(kHistory == GalerkinWarmStart::kBasis);
  const Small symmetric = 0.5 * (gram + gram.transpose());
  const SmallVector combination = GalerkinWarmStart::coefficients(symmetric, projected);
  // w0, and its residual from the products already made: S (b - A u_k) - S A S w0 (a zero
  // combination when it was not finite).
  for (int v = 0; v < num_vertices_; ++v) {
    for (int a = 0; a < 3; ++a) {
      solution_(3 * v + a) = combination.dot(basis_.col(v).segment<kHistory>(kHistory * a));
      residual_(3 * v + a) -=
          combination.dot(basis_products_.col(v).segment<kHistory>(kHistory * a));
    }
  }
}

void SpringSystem::multiply_history() {
  static_assert(kHistory % 2 == 0);
  constexpr int kHalves = kHistory / 2;  // pairs of vectors
  constexpr int kColumn = 3 * kHistory;
  const Springs springs = springs_of(coefficients_);
  const double* w = basis_.data();
  double* out = basis_products_.data();
  for (int v = 0; v < num_vertices_; ++v) {
    for (int i = 0; i < kColumn; ++i) {
      out[kColumn * v + i] = masses_(v) * w[kColumn * v + i];
    }
  }
  for (std::size_t k = 0; k < penalty_vertices_.size(); ++k) {
    const int v = penalty_vertices_[k];
    for (int h = 0; h < kHistory; ++h) {
      const Eigen::Map<const Eigen::Vector3d, 0, Eigen::InnerStride<kHistory>> value(w + kColumn * v
                                                                                     + h);
      Eigen::Map<Eigen::Vector3d, 0, Eigen::InnerStride<kHistory>> pushed(out + kColumn * v + h);
      pushed += penalties_[k] * value;
    }
  }
  for (int v = 0; v < num_vertices_; ++v) {
    // Per spring, B_e (w_v - w_j) for every vector onto v (summed) and, negated, onto j.
    Pair own[3][kHalves];
    Pair sum[3][kHalves];
    for (int a = 0; a < 3; ++a) {
      for (int h = 0; h < kHalves; ++h) {
        own[a][h] = load_pair(w + kColumn * v + kHistory * a + 2 * h);
        sum[a][h] = Pair{0.0, 0.0};
      }
    }
    for (int e = owned_offsets_[static_cast<std::size_t>(v)];
         e < owned_offsets_[static_cast<std::size_t>(v) + 1]; ++e) {
      const int j = others_[static_cast<std::size_t>(e)];
      const Pair ux = {springs.ux[e], springs.ux[e]};
      const Pair uy = {springs.uy[e], springs.uy[e]};
      const Pair uz = {springs.uz[e], springs.uz[e]};
      const Pair across = {springs.across[e], springs.across[e]};
      for (int h = 0; h < kHalves; ++h) {
        const double* wj = w + kColumn * j + 2 * h;
        double* oj = out + kColumn * j + 2 * h;
        const Pair r0 = own[0][h] - load_pair(wj);
        const Pair r1 = own[1][h] - load_pair(wj + kHistory);
        const Pair r2 = own[2][h] - load_pair(wj + 2 * kHistory);
        const Pair along = ux * r0 + uy * r1 + uz * r2;
        const Pair f0 = ux * along + across * r0;
        const Pair f1 = uy * along + across * r1;
        const Pair f2 = uz * along + across * r2;
        sum[0][h] += f0;
        sum[1][h] += f1;
        sum[2][h] += f2;
        store_pair(oj, load_pair(oj) - f0);
        store_pair(oj + kHistory, load_pair(oj + kHistory) - f1);
        store_pair(oj + 2 * kHistory, load_pair(oj + 2 * kHistory) - f2);
      }
    }
    for (int a = 0; a < 3; ++a) {
      for (int h = 0; h < kHalves; ++h) {
        double* ov = out + kColumn * v + kHistory * a + 2 * h;
        store_pair(ov, load_pair(ov) + sum[a][h]);
      }
    }
  }
  for (const int c : held_vertices_) {
    for (int h = 0; h < kHistory; ++h) {
      Eigen::Map<Eigen::Vector3d, 0, Eigen::InnerStride<kHistory>> value(out + kColumn * c + h);
      value = filter(c, value);
    }
  }
}

[[gnu::always_inline]] inline void SpringSystem::owned_sum(int v,
                                                           const double* x,
                                                           double* sum) const {
  const Springs springs = springs_of(coefficients_);
  const int end = owned_offsets_[static_cast<std::size_t>(v) + 1];
  int e = owned_offsets_[static_cast<std::size_t>(v)];
  Pair a0 = {0.0, 0.0};
  Pair a1 = {0.0, 0.0};
  Pair a2 = {0.0, 0.0};
  for (; e + 1 < end; e += 2) {
    const double* x1 = x + other_coordinates_[static_cast<std::size_t>(e)];
    const double* x2 = x + other_coordinates_[static_cast<std::size_t>(e) + 1];
    const Pair xx = {x1[0], x2[0]};
    const Pair xy = {x1[1], x2[1]};
    const Pair xz = {x1[2], x2[2]};
    const Pair ux = load_pair(springs.ux + e);
    const Pair uy = load_pair(springs.uy + e);
    const Pair uz = load_pair(springs.uz + e);
    const Pair across = load_pair(springs.across + e);
    const Pair along = ux * xx + uy * xy + uz * xz;
    a0 += ux * along + across * xx;
    a1 += uy * along + across * xy;
    a2 += uz * along + across * xz;
  }
  sum[0] = a0[0] + a0[1];
  sum[1] = a1[0] + a1[1];
  sum[2] = a2[0] + a2[1];
  if (e < end) {
    double f[3];
    springs.apply(e, x + other_coordinates_[static_cast<std::size_t>(e)], f);
    sum[0] += f[0];
    sum[1] += f[1];
    sum[2] += f[2];
  }
}

[[gnu::always_inline]] inline void SpringSystem::push_owned(int v,
                                                            const double* y,
                                                            double* out) const {
  const Springs springs = springs_of(coefficients_);
  const int end = owned_offsets_[static_cast<std::size_t>(v) + 1];
  int e = owned_offsets_[static_cast<std::size_t>(v)];
  const Pair y0 = {y[0], y[0]};
  const Pair y1 = {y[1], y[1]};
  const Pair y2 = {y[2], y[2]};
  for (; e + 1 < end; e += 2) {
    const Pair ux = load_pair(springs.ux + e);
    const Pair uy = load_pair(springs.uy + e);
    const Pair uz = load_pair(springs.uz + e);
    const Pair across = load_pair(springs.across + e);
    const Pair along = ux * y0 + uy * y1 + uz * y2;
    const Pair fx = ux * along + across * y0;
    const Pair fy = uy * along + across * y1;
    const Pair fz = uz * along + across * y2;
    double* o1 = out + other_coordinates_[static_cast<std::size_t>(e)];
    double* o2 = out + other_coordinates_[static_cast<std::size_t>(e) + 1];
    o1[0] += fx[0];
    o1[1] += fy[0];
    o1[2] += fz[0];
    o2[0] += fx[1];
    o2[1] += fy[1];
    o2[2] += fz[1];
  }
  if (e < end) {
    double f[3];
    springs.apply(e, y, f);
    double* o = out + other_coordinates_[static_cast<std::size_t>(e)];
    o[0] += f[0];
    o[1] += f[1];
    o[2] += f[2];
  }
}

[[gnu::always_inline]] inline void SpringSystem::filter_in_place(int v, double* value) const {
  if (kinds_[static_cast<std::size_t>(v)] != kFree) {
    const Eigen::Vector3d filtered = filter(v, Eigen::Vector3d(value[0], value[1], value[2]));
    value[0] = filtered.x();
    value[1] = filtered.y();
    value[2] = filtered.z();
  }
}

SolveReport SpringSystem::solve_ssor(double tolerance,
                                     int max_iterations,
                                     double reference_energy) {
  SolveReport report;
  const Eigen::Index size = rhs_.size();
  const double* filtered = filtered_.data();
  const double* inverse = inverse_.data();
  double* w = solution_.data();
  double* r = residual_.data();
  double* z = preconditioned_.data();
  double* p = direction_.data();
  double* q = product_.data();
  double* t = sweep_.data();

  // CG on the correction d = w - w0, from d0 = 0: its transform x^ = (D + U) d starts at 0 and
  // r^ = (D + L)^-1 r0, with r0 = S (b - A w0) from the warm start (no product here).
  double* x_hat = transformed_.data();
  std::fill(x_hat, x_hat + size, 0.0);
  for (int v = 0; v < num_vertices_; ++v) {
    // (D + L) y = r0 in place: r0_v is read before y_v is written, and push_owned only changes
    // higher vertices.
    double y[3];
    sym_multiply(inverse + 6 * v, r + 3 * v, y);
    std::copy(y, y + 3, r + 3 * v);
    push_owned(v, y, r);
  }
  const auto apply_d = [filtered](int v, const double* in, double* out) {
    sym_multiply(filtered + 6 * v, in, out);
  };
  const std::array<int, 2> whole{0, num_vertices_};  // one range: the sweeps are sequential
  const EisenstatStart start = eisenstat_start(whole, r, x_hat, r, z, p, apply_d);
  const double first_residual = std::sqrt(start.residual_squared);

  EnergyErrorEstimate estimate(reference_energy);
  report.converged = first_residual == 0.0;
  eisenstat_iterations(
      whole, x_hat, r, z, p, q, start.rz, kRoundoff * first_residual, tolerance, max_iterations,
      estimate, report,
      [this](double beta) {
        backward_sweep(beta);
        return forward_sweep();
      },
      apply_d);

  // w = w0 + (D + U)^-1 x^ ...
  for (int v = num_vertices_ - 1; v >= 0; --v) {
    double sum[3];
    owned_sum(v, t, sum);
    const double total[3] = {x_hat[3 * v] + sum[0], x_hat[3 * v + 1] + sum[1],
                             x_hat[3 * v + 2] + sum[2]};
    sym_multiply(inverse + 6 * v, total, t + 3 * v);
  }
  for (Eigen::Index i = 0; i < size; ++i) {
    w[i] += t[i];
  }
  // ... and the constrained system's residual (D + L) r^.
  for (int v = 0; v < num_vertices_; ++v) {
    sym_multiply(filtered + 6 * v, r + 3 * v, q + 3 * v);
  }
  for (int v = 0; v < num_vertices_; ++v) {
    const double minus[3] = {-r[3 * v], -r[3 * v + 1], -r[3 * v + 2]};
    push_owned(v, minus, q);
  }
  for (const int c : held_vertices_) {
    filter_in_place(c, q + 3 * c);
  }
  translation_correction(w, q);
  report.residual = product_.norm();
  return report;
}

void SpringSystem::backward_sweep(double beta) {
  const double* inverse = inverse_.data();
  const double* z = preconditioned_.data();
  double* p = direction_.data();
  double* t = sweep_.data();
  double* g = carry_.data();
  for (int v = num_vertices_ - 1; v >= 0; --v) {
    const double pv[3] = {z[3 * v] + beta * p[3 * v], z[3 * v + 1] + beta * p[3 * v + 1],
                          z[3 * v + 2] + beta * p[3 * v + 2]};
    p[3 * v] = pv[0];
    p[3 * v + 1] = pv[1];
    p[3 * v + 2] = pv[2];
    // t_v = D_v^+ (p_v - (U t)_v), (U t)_v = -S sum_owned B_e t_j; and g_v = p_v - D_v t_v,
    // which is -S sum_owned B_e t_j (D_v D_v^+ = S, and p_v = S p_v).
    double sum[3];
    owned_sum(v, t, sum);
    const double total[3] = {pv[0] + sum[0], pv[1] + sum[1], pv[2] + sum[2]};
    sym_multiply(inverse + 6 * v, total, t + 3 * v);
    filter_in_place(v, sum);
    g[3 * v] = -sum[0];
    g[3 * v + 1] = -sum[1];
    g[3 * v + 2] = -sum[2];
  }
}

double SpringSystem::forward_sweep() {
  const double* inverse = inverse_.data();
  const double* p = direction_.data();
  const double* t = sweep_.data();
  double* g = carry_.data();
  double* q = product_.data();
  double curvature = 0.0;
  for (int v = 0; v < num_vertices_; ++v) {
    // y_v = D_v^+ (g_v - (L y)_v), the springs to lower vertices having pushed theirs into g.
    double y[3];
    sym_multiply(inverse + 6 * v, g + 3 * v, y);
    const double qv[3] = {t[3 * v] + y[0], t[3 * v + 1] + y[1], t[3 * v + 2] + y[2]};
    q[3 * v] = qv[0];
    q[3 * v + 1] = qv[1];
    q[3 * v + 2] = qv[2];
    curvature += dot3(p + 3 * v, qv);
    push_owned(v, y, g);
  }
  return curvature;
}

double SpringSystem::filtered_multiply(const double* w, double* out) const {
  const Springs springs = springs_of(coefficients_);
  for (int v = 0; v < num_vertices_; ++v) {
    for (int a = 0; a < 3; ++a) {
      out[3 * v + a] = masses_(v) * w[3 * v + a];
    }
  }
  for (std::size_t k = 0; k < penalty_vertices_.size(); ++k) {
    const int v = penalty_vertices_[k];
    const Eigen::Vector3d extra = penalties_[k] * Eigen::Map<const Eigen::Vector3d>(w + 3 * v);
    out[3 * v] += extra.x();
    out[3 * v + 1] += extra.y();
    out[3 * v + 2] += extra.z();
  }
  for (int v = 0; v < num_vertices_; ++v) {
    // B_e (w_v - w_j) onto v (summed) and, negated, onto j; the springs two at a time.
    const double* wv = w + 3 * v;
    const int end = owned_offsets_[static_cast<std::size_t>(v) + 1];
    int e = owned_offsets_[static_cast<std::size_t>(v)];
    const Pair x0 = {wv[0], wv[0]};
    const Pair x1 = {wv[1], wv[1]};
    const Pair x2 = {wv[2], wv[2]};
    Pair a0 = {0.0, 0.0};
    Pair a1 = {0.0, 0.0};
    Pair a2 = {0.0, 0.0};
    for (; e + 1 < end; e += 2) {
      const double* w1 = w + other_coordinates_[static_cast<std::size_t>(e)];
      const double* w2 = w + other_coordinates_[static_cast<std::size_t>(e) + 1];
      const Pair r0 = x0 - Pair{w1[0], w2[0]};
      const Pair r1 = x1 - Pair{w1[1], w2[1]};
      const Pair r2 = x2 - Pair{w1[2], w2[2]};
      const Pair ux = load_pair(springs.ux + e);
      const Pair uy = load_pair(springs.uy + e);
      const Pair uz = load_pair(springs.uz + e);
      const Pair across = load_pair(springs.across + e);
      const Pair along = ux * r0 + uy * r1 + uz * r2;
      const Pair f0 = ux * along + across * r0;
      const Pair f1 = uy * along + across * r1;
      const Pair f2 = uz * along + across * r2;
      a0 += f0;
      a1 += f1;
      a2 += f2;
      double* o1 = out + other_coordinates_[static_cast<std::size_t>(e)];
      double* o2 = out + other_coordinates_[static_cast<std::size_t>(e) + 1];
      o1[0] -= f0[0];
      o1[1] -= f1[0];
      o1[2] -= f2[0];
      o2[0] -= f0[1];
      o2[1] -= f1[1];
      o2[2] -= f2[1];
    }
    double sum[3] = {a0[0] + a0[1], a1[0] + a1[1], a2[0] + a2[1]};
    if (e < end) {
      const int j = others_[static_cast<std::size_t>(e)];
      const double* wj = w + 3 * j;
      const double r[3] = {wv[0] - wj[0], wv[1] - wj[1], wv[2] - wj[2]};
      double f[3];
      springs.apply(e, r, f);
      for (int a = 0; a < 3; ++a) {
        sum[a] += f[a];
        out[3 * j + a] -= f[a];
      }
    }
    out[3 * v] += sum[0];
    out[3 * v + 1] += sum[1];
    out[3 * v + 2] += sum[2];
  }
  for (const int c : held_vertices_) {
    const Eigen::Vector3d value(out[3 * c], out[3 * c + 1], out[3 * c + 2]);
    const Eigen::Vector3d filtered = filter(c, value);
    out[3 * c] = filtered.x();
    out[3 * c + 1] = filtered.y();
    out[3 * c + 2] = filtered.z();
  }
  double curvature = 0.0;
  for (Eigen::Index i = 0; i < 3 * static_cast<Eigen::Index>(num_vertices_); ++i) {
    curvature += w[i] * out[i];
  }
  return curvature;
}

SolveReport SpringSystem::solve_block_jacobi(double tolerance,
                                             int max_iterations,
                                             double reference_energy) {
  SolveReport report;
  double* w = solution_.data();
  double* r = residual_.data();
  double* z = preconditioned_.data();
  double* p = direction_.data();
  double* q = product_.data();

  // r0 = S (b - A w0) from the warm start.
  double rz = 0.0;
  double residual_squared = 0.0;
  for (int v = 0; v < num_vertices_; ++v) {
    sym_multiply(inverse_.col(v).data(), r + 3 * v, z + 3 * v);
    for (int a = 0; a < 3; ++a) {
      p[3 * v + a] = z[3 * v + a];
    }
    rz += dot3(r + 3 * v, z + 3 * v);
    residual_squared += dot3(r + 3 * v, r + 3 * v);
  }
  const double rhs_norm = rhs_.norm();
  double residual_norm = std::sqrt(residual_squared);
  EnergyErrorEstimate estimate(reference_energy);
  report.converged = residual_norm == 0.0;
  while (!report.converged && report.iterations < max_iterations) {
    ++report.iterations;
    const double curvature = filtered_multiply(p, q);
    if (!(curvature > 0.0) || !std::isfinite(rz)) {
      break;
    }
    const double alpha = rz / curvature;
    report.error = estimate.add(report.iterations, alpha * rz);
    double rz_next = 0.0;
    residual_squared = 0.0;
    for (int v = 0; v < num_vertices_; ++v) {
      double* rv = r + 3 * v;
      for (int a = 0; a < 3; ++a) {
        w[3 * v + a] += alpha * p[3 * v + a];
        rv[a] -= alpha * q[3 * v + a];
      }
      sym_multiply(inverse_.col(v).data(), rv, z + 3 * v);
      rz_next += dot3(rv, z + 3 * v);
      residual_squared += dot3(rv, rv);
    }
    residual_norm = std::sqrt(residual_squared);
    if (residual_norm <= kRoundoff * rhs_norm || rz_next == 0.0
        || estimate.met(report.iterations, tolerance)) {
      report.converged = true;
      break;
    }
    const double beta = rz_next / rz;
    rz = rz_next;
    for (Eigen::Index i = 0; i < rhs_.size(); ++i) {
      p[i] = z[i] + beta * p[i];
    }
  }
  translation_correction(w, r);
  report.residual = residual_.norm();
  return report;
}

void SpringSystem::translation_correction(double* w, double* r) const {
  // Z^T A Z and Z^T r. A spring between two free vertices does not resist a translation
  // (Z_i - Z_j = 0): only the vertices' own terms and the springs at held vertices count.
  // S m S = m S, which is m I but at the held vertices.
  double mass = 0.0;
  Eigen::Vector3d residual_sum = Eigen::Vector3d::Zero();
  for (int v = 0; v < num_vertices_; ++v) {
    residual_sum += Eigen::Map<const Eigen::Vector3d>(r + 3 * v);  // r = S r
    mass += masses_(v);
  }
  Eigen::Matrix3d coarse = mass * Eigen::Matrix3d::Identity();
  for (const int c : held_vertices_) {
    coarse += masses_(c) * (filter_matrix(c) - Eigen::Matrix3d::Identity());
  }
  for (std::size_t k = 0; k < penalty_vertices_.size(); ++k) {
    coarse += penalties_[k];  // at free vertices (S = I)
  }
  for_each_held_spring([&](Eigen::Index e, int i, int j) {
    const Kind first = kinds_[static_cast<std::size_t>(i)];
    const Kind second = kinds_[static_cast<std::size_t>(j)];
    if (first != kSliding && second != kSliding) {
      // S_i - S_j is +-I between a free and a fixed vertex (the usual held spring), 0 between
      // two fixed ones.
      if ((first == kFree) != (second == kFree)) {
        coarse += spring_block(e);
      }
      return;
    }
    const Eigen::Matrix3d difference = filter_matrix(i) - filter_matrix(j);
    coarse += difference.transpose() * spring_block(e) * difference;
  });
  const Eigen::Vector3d shift = coarse.ldlt().solve(residual_sum);
  if (!shift.allFinite() || shift.squaredNorm() == 0.0) {
    return;
  }
  // w += Z c, and r -= S A Z c.
  for (int v = 0; v < num_vertices_; ++v) {
    const Eigen::Vector3d moved =
        kinds_[static_cast<std::size_t>(v)] == kFree ? shift : filter(v, shift);
    for (int a = 0; a < 3; ++a) {
      w[3 * v + a] += moved(a);
      r[3 * v + a] -= masses_(v) * moved(a);
    }
  }
  for (std::size_t k = 0; k < penalty_vertices_.size(); ++k) {
    Eigen::Map<Eigen::Vector3d>(r + 3 * penalty_vertices_[k]) -= penalties_[k] * shift;
  }
  for_each_held_spring([&](Eigen::Index e, int i, int j) {
    const Eigen::Vector3d force = spring_block(e) * (filter(i, shift) - filter(j, shift));
    Eigen::Map<Eigen::Vector3d>(r + 3 * i) -= filter(i, force);
    Eigen::Map<Eigen::Vector3d>(r + 3 * j) += filter(j, force);
  });
}

std::size_t SpringSystem::memory_bytes() const {
  const auto ints = owned_offsets_.size() + others_.size() + other_coordinates_.size()
                    + firsts_.size() + incident_offsets_.size() + incident_springs_.size()
                    + slots_.size() + held_vertices_.capacity() + penalty_vertices_.capacity();
  const auto doubles =
      static_cast<std::size_t>(coefficients_.size() + masses_.size() + diagonal_.size()
                               + filtered_.size() + inverse_.size())
      + (10 + 3 * static_cast<std::size_t>(kHistory)) * static_cast<std::size_t>(rhs_.size());
  return ints * sizeof(int) + doubles * sizeof(double) + kinds_.size()
         + (held_.capacity() + held_filters_.capacity() + penalties_.capacity())
               * sizeof(Eigen::Matrix3d);
}

}  // namespace softbench::mass_spring
