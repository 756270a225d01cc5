// SPDX-License-Identifier: MIT
// The XPBD step: substeps, the Gauss-Seidel sweep over the tets, holds and their forces.
#include "models/finite_state.h"
#include "models/xpbd/xpbd_model.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <span>

namespace softbench::xpbd {
namespace {

/// Below this I_C (|F| < 1e-150: a tet collapsed to a point) C_D's gradient is taken as zero:
/// its direction is undefined there.
constexpr double kCollapsedInvariant = 1e-300;

}  // namespace

void XpbdModel::bind(const StepInput& input) {
  constraints_.bind(input.constraints);
  for (const int v : constraints_.vertices()) {
    const auto vertex = static_cast<std::size_t>(v);
    const PositionConstraint& constraint = *constraints_.of(v);
    const double w = inverse_masses_[v];
    const bool exact = is_exact(&constraint);
    holds_[vertex] = exact ? Hold::kExact : Hold::kPenalty;
    // An exact hold removes the held directions from the vertex's mobility: the projections
    // move it only along the free ones.
    mobility_[vertex] = exact ? Eigen::Matrix3d((Eigen::Matrix3d::Identity() - constraint.held) * w)
                              : Eigen::Matrix3d(Eigen::Matrix3d::Identity() * w);
    starts_.col(v) = positions_.col(v);
    for (int k = vertex_offsets_[vertex]; k < vertex_offsets_[vertex + 1]; ++k) {
      general_[static_cast<std::size_t>(vertex_tets_[static_cast<std::size_t>(k)])] = 1;
    }
  }
}

void XpbdModel::unbind() {
  for (const int v : constraints_.vertices()) {
    const auto vertex = static_cast<std::size_t>(v);
    holds_[vertex] = Hold::kFree;
    for (int k = vertex_offsets_[vertex]; k < vertex_offsets_[vertex + 1]; ++k) {
      general_[static_cast<std::size_t>(vertex_tets_[static_cast<std::size_t>(k)])] = 0;
    }
  }
  constraints_.unbind();
}

Eigen::Vector3d XpbdModel::place(int vertex, const Eigen::Vector3d& x, int s, int n) const {
  const PositionConstraint& constraint = *constraints_.of(vertex);
  if (s == n) {
    return constraint.place(x);  // the step's target itself: the step ends on it
  }
  // The target moves in a straight line over the step: a hold that moves by d in a step moves
  // its vertex by d / n per substep instead of all at once in the first (a jump the tets around
  // it would answer with an impulse n times too large).
  const double fraction = static_cast<double>(s) / static_cast<double>(n);
  const Eigen::Vector3d target =
      starts_.col(vertex) + fraction * (constraint.target - starts_.col(vertex));
  return constraint.slides() ? Eigen::Vector3d(x + constraint.held * (target - x)) : target;
}

namespace {

/// Two tets' values side by side (GCC's and Clang's vector extension): the sweep projects two
/// tets that share no vertex at once, every arithmetic operation on both, in the same order as
/// for one (so a tet's result does not depend on whether it was paired).
using Pair = double __attribute__((vector_size(16)));

/// C_D = sqrt(I_C - log(I_C + 1)) (positive for I_C > 0).
inline double deviatoric(double invariant) {
  return std::sqrt(invariant - std::log1p(invariant));
}
inline Pair deviatoric(Pair invariant) {
  return Pair{deviatoric(invariant[0]), deviatoric(invariant[1])};
}
/// dC_D/dF = s F with s = (1 - 1/(I_C + 1)) / C_D = I_C / ((I_C + 1) C_D): this s.
inline double gradient_scale(double invariant, double constraint) {
  return invariant > kCollapsedInvariant ? invariant / ((invariant + 1.0) * constraint) : 0.0;
}
inline Pair gradient_scale(Pair invariant, Pair constraint) {
  return Pair{gradient_scale(invariant[0], constraint[0]),
              gradient_scale(invariant[1], constraint[1])};
}
inline double positive_part(double x) {
  return x > 0.0 ? x : 0.0;
}
inline Pair positive_part(Pair x) {
  return Pair{positive_part(x[0]), positive_part(x[1])};
}

/// One tet's (or a pair's) gradients. With Ds = [x1 - x0, x2 - x0, x3 - x0], R = Dm^-1 and
/// F = Ds R, the gradients at vertices 1..3 are the columns of dC/dF R^T:
///   C_D: s F R^T = s Ds S, S = R R^T (per tet), and I_C = |F|^2 = <Ds S, Ds>;
///   C_H: cof(F) R^T = cof(Ds) cof(R) R^T = det(R) cof(Ds), and J = det(R) det(Ds),
/// so F itself is never formed (a third fewer operations than through F), and the factors
/// s and det R are applied to the multipliers instead of to the gradients. Written out
/// in scalars: Eigen's 3-vector expressions mixed packets and scalars and spent many of the
/// sweep's instructions moving values between registers.
template <class T>
struct Gradients {
  T q[4][3];  ///< q[a], a = 1..3: column a-1 of Ds S; q[0] = -(q1 + q2 + q3)
  T k[4][3];  ///< k[a], a = 1..3: column a-1 of cof(Ds); k[0] likewise
  T invariant;
  T volume_ratio;  ///< J

  Gradients(const T (&e)[3][3], const T (&m)[6], T det_rest_inverse) {
    const T s[3][3] = {{m[0], m[3], m[4]}, {m[3], m[1], m[5]}, {m[4], m[5], m[2]}};
    for (int a = 1; a < 4; ++a) {
      for (int i = 0; i < 3; ++i) {
        q[a][i] = e[0][i] * s[0][a - 1] + e[1][i] * s[1][a - 1] + e[2][i] * s[2][a - 1];
      }
    }
    for (int a = 1; a < 4; ++a) {
      const T* u = e[a % 3];
      const T* v = e[(a + 1) % 3];
      k[a][0] = u[1] * v[2] - u[2] * v[1];
      k[a][1] = u[2] * v[0] - u[0] * v[2];
      k[a][2] = u[0] * v[1] - u[1] * v[0];
    }
    for (int i = 0; i < 3; ++i) {
      q[0][i] = -(q[1][i] + q[2][i] + q[3][i]);
      k[0][i] = -(k[1][i] + k[2][i] + k[3][i]);
    }
    invariant = q[1][0] * e[0][0] + q[1][1] * e[0][1] + q[1][2] * e[0][2];
    for (int a = 2; a < 4; ++a) {
      invariant += q[a][0] * e[a - 1][0] + q[a][1] * e[a - 1][1] + q[a][2] * e[a - 1][2];
    }
    volume_ratio = det_rest_inverse * (e[0][0] * k[1][0] + e[0][1] * k[1][1] + e[0][2] * k[1][2]);
  }
};

/// The 2x2 system [A + diag(alpha~)] dlambda = -C - alpha~ lambda of one tet (or a pair), from
/// the Gram matrix b of the unscaled gradients q, k under the inverse masses. A is positive
/// semi-definite (at rest singular: the gradients are parallel), so its determinant is clamped
/// at 0 against round-off and the system's stays >= alpha~_D alpha~_H > 0. Returns in `cd`, `ch`
/// the coefficients of the impulse on vertex a: dlambda_D g_D,a + dlambda_H g_H,a = cd q_a + ch
/// k_a; updates lambda.
template <class T>
inline void solve_pair_system(const Gradients<T>& g,
                              T b11,
                              T b12,
                              T b22,
                              T det_rest_inverse,
                              T alpha_d,
                              T alpha_h,
                              double alpha,
                              T& lambda_d,
                              T& lambda_h,
                              T& cd,
                              T& ch) {
  const T constraint = deviatoric(g.invariant);
  const T scale = gradient_scale(g.invariant, constraint);
  const T a11 = scale * scale * b11;
  const T a12 = scale * det_rest_inverse * b12;
  const T a22 = det_rest_inverse * det_rest_inverse * b22;
  const T rd = -(constraint + alpha_d * lambda_d);
  const T rh = -(g.volume_ratio - alpha + alpha_h * lambda_h);
  const T determinant =
      positive_part(a11 * a22 - a12 * a12) + alpha_d * a22 + alpha_h * a11 + alpha_d * alpha_h;
  const T inverse = 1.0 / determinant;
  const T dd = ((a22 + alpha_h) * rd - a12 * rh) * inverse;
  const T dh = ((a11 + alpha_d) * rh - a12 * rd) * inverse;
  lambda_d += dd;
  lambda_h += dh;
  cd = dd * scale;
  ch = dh * det_rest_inverse;
}

}  // namespace

template <bool kGeneral>
inline void XpbdModel::project_tet(std::size_t t,
                                   double deviatoric_compliance,
                                   double hydrostatic_compliance) {
  const Tet& tet = tets_[t];
  double* const x = positions_.data();
  double* p[4];
  for (int a = 0; a < 4; ++a) {
    p[a] = x + 3 * tet.vertices[a];
  }
  double e[3][3];  // e[k]: the edge x_(k+1) - x_0
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 3; ++i) {
      e[k][i] = p[k + 1][i] - p[0][i];
    }
  }
  const Gradients<double> g(e, tet.metric, tet.det_rest_inverse);
  double b11 = 0.0;
  double b12 = 0.0;
  double b22 = 0.0;
  for (int a = 0; a < 4; ++a) {
    const int v = tet.vertices[a];
    if (kGeneral && holds_[static_cast<std::size_t>(v)] != Hold::kFree) {
      const Eigen::Matrix3d& mobility = mobility_[static_cast<std::size_t>(v)];
      const Eigen::Map<const Eigen::Vector3d> d(g.q[a]);
      const Eigen::Map<const Eigen::Vector3d> h(g.k[a]);
      const Eigen::Vector3d wh = mobility * h;
      b11 += d.dot(mobility * d);
      b12 += d.dot(wh);
      b22 += h.dot(wh);
    } else {
      const double w = inverse_masses_[v];
      b11 += w * (g.q[a][0] * g.q[a][0] + g.q[a][1] * g.q[a][1] + g.q[a][2] * g.q[a][2]);
      b12 += w * (g.q[a][0] * g.k[a][0] + g.q[a][1] * g.k[a][1] + g.q[a][2] * g.k[a][2]);
      b22 += w * (g.k[a][0] * g.k[a][0] + g.k[a][1] * g.k[a][1] + g.k[a][2] * g.k[a][2]);
    }
  }
  Eigen::Vector2d& lambda = multipliers_[t];
  double cd = 0.0;
  double ch = 0.0;
  solve_pair_system(
      g, b11, b12, b22, tet.det_rest_inverse, tet.inverse_volume * deviatoric_compliance,
      tet.inverse_volume * hydrostatic_compliance, law_.alpha, lambda[0], lambda[1], cd, ch);
  for (int a = 0; a < 4; ++a) {
    const int v = tet.vertices[a];
    double impulse[3];
    for (int i = 0; i < 3; ++i) {
      impulse[i] = cd * g.q[a][i] + ch * g.k[a][i];
    }
    if (kGeneral && holds_[static_cast<std::size_t>(v)] != Hold::kFree) {
      const Eigen::Map<const Eigen::Vector3d> j(impulse);
      Eigen::Map<Eigen::Vector3d>(p[a]) += mobility_[static_cast<std::size_t>(v)] * j;
      impulses_.col(v) += j;
    } else {
      const double w = inverse_masses_[v];
      for (int i = 0; i < 3; ++i) {
        p[a][i] += w * impulse[i];
      }
    }
  }
}

inline void XpbdModel::project_pair(std::size_t t,
                                    double deviatoric_compliance,
                                    double hydrostatic_compliance) {
  // Tets t and t + 1 share no vertex (paired_), nothing held: projecting them together is
  // projecting them one after the other.
  const Tet& first = tets_[t];
  const Tet& second = tets_[t + 1];
  double* const x = positions_.data();
  double* p[2][4];
  Pair w[4];
  for (int a = 0; a < 4; ++a) {
    p[0][a] = x + 3 * first.vertices[a];
    p[1][a] = x + 3 * second.vertices[a];
    w[a] = Pair{inverse_masses_[first.vertices[a]], inverse_masses_[second.vertices[a]]};
  }
  Pair e[3][3];
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 3; ++i) {
      e[k][i] = Pair{p[0][k + 1][i], p[1][k + 1][i]} - Pair{p[0][0][i], p[1][0][i]};
    }
  }
  Pair m[6];
  for (int c = 0; c < 6; ++c) {
    m[c] = Pair{first.metric[c], second.metric[c]};
  }
  const Pair det_rest_inverse{first.det_rest_inverse, second.det_rest_inverse};
  const Gradients<Pair> g(e, m, det_rest_inverse);
  Pair b11 = w[0] * (g.q[0][0] * g.q[0][0] + g.q[0][1] * g.q[0][1] + g.q[0][2] * g.q[0][2]);
  Pair b12 = w[0] * (g.q[0][0] * g.k[0][0] + g.q[0][1] * g.k[0][1] + g.q[0][2] * g.k[0][2]);
  Pair b22 = w[0] * (g.k[0][0] * g.k[0][0] + g.k[0][1] * g.k[0][1] + g.k[0][2] * g.k[0][2]);
  for (int a = 1; a < 4; ++a) {
    b11 += w[a] * (g.q[a][0] * g.q[a][0] + g.q[a][1] * g.q[a][1] + g.q[a][2] * g.q[a][2]);
    b12 += w[a] * (g.q[a][0] * g.k[a][0] + g.q[a][1] * g.k[a][1] + g.q[a][2] * g.k[a][2]);
    b22 += w[a] * (g.k[a][0] * g.k[a][0] + g.k[a][1] * g.k[a][1] + g.k[a][2] * g.k[a][2]);
  }
  Eigen::Vector2d& first_lambda = multipliers_[t];
  Eigen::Vector2d& second_lambda = multipliers_[t + 1];
  Pair lambda_d{first_lambda[0], second_lambda[0]};
  Pair lambda_h{first_lambda[1], second_lambda[1]};
  const Pair inverse_volume{first.inverse_volume, second.inverse_volume};
  Pair cd;
  Pair ch;
  solve_pair_system(g, b11, b12, b22, det_rest_inverse, inverse_volume * deviatoric_compliance,
                    inverse_volume * hydrostatic_compliance, law_.alpha, lambda_d, lambda_h, cd,
                    ch);
  first_lambda = Eigen::Vector2d(lambda_d[0], lambda_h[0]);
  second_lambda = Eigen::Vector2d(lambda_d[1], lambda_h[1]);
  for (int a = 0; a < 4; ++a) {
    for (int i = 0; i < 3; ++i) {
      const Pair change = w[a] * (cd * g.q[a][i] + ch * g.k[a][i]);
      p[0][a][i] += change[0];
      p[1][a][i] += change[1];
    }
  }
}

void XpbdModel::sweep_tets(double deviatoric_compliance, double hydrostatic_compliance) {
  const std::size_t count = tets_.size();
  std::size_t t = 0;
  while (t < count) {
    if (paired_[t] != 0 && general_[t] == 0 && general_[t + 1] == 0) {
      project_pair(t, deviatoric_compliance, hydrostatic_compliance);
      t += 2;
    } else if (general_[t] != 0) {
      project_tet<true>(t, deviatoric_compliance, hydrostatic_compliance);
      ++t;
    } else {
      project_tet<false>(t, deviatoric_compliance, hydrostatic_compliance);
      ++t;
    }
  }
}

void XpbdModel::sweep(double substep) {
  deviatoric_compliance_ = 1.0 / (law_.mu * substep * substep);
  hydrostatic_compliance_ = 1.0 / (law_.lambda * substep * substep);
  std::fill(multipliers_.begin(), multipliers_.end(), Eigen::Vector2d::Zero());
  sweep_tets(deviatoric_compliance_, hydrostatic_compliance_);
}

double XpbdModel::residual() const {
  double worst = 0.0;
  for (std::size_t t = 0; t < tets_.size(); ++t) {
    const Tet& tet = tets_[t];
    const Eigen::Matrix3d f = deformation(t);
    const Eigen::Vector2d& lambda = multipliers_[t];
    const double rd = std::abs(deviatoric(f.squaredNorm())
                               + tet.inverse_volume * deviatoric_compliance_ * lambda[0]);
    const double rh = std::abs(f.determinant() - law_.alpha
                               + tet.inverse_volume * hydrostatic_compliance_ * lambda[1]);
    // Written so that a NaN propagates.
    if (!(rd <= worst)) {
      worst = rd;
    }
    if (!(rh <= worst)) {
      worst = rh;
    }
  }
  return worst;
}

StepStats XpbdModel::step(double dt, const StepInput& input) {
  StepStats stats;
  bind(input);
  const int n = substeps_for(dt);
  const double h = dt / n;
  const double h2 = h * h;
  deviatoric_compliance_ = 1.0 / (law_.mu * h2);
  hydrostatic_compliance_ = 1.0 / (law_.lambda * h2);
  const double drag = 1.0 / (1.0 + h * params_.mass_damping);
  const Eigen::Vector3d fall = h2 * input.gravity;
  const std::span<const int> held = constraints_.vertices();
  constraint_forces_.setZero();

  int substeps = 0;
  for (int s = 1; s <= n; ++s) {
    ++substeps;
    previous_ = positions_;
    if (params_.mass_damping > 0.0) {
      velocities_ *= drag;
    }
    positions_ += h * velocities_;
    positions_.colwise() += fall;
    if (input.external_forces != nullptr) {
      positions_ += h2 * (*input.external_forces * inverse_masses_.asDiagonal());
    }
    for (const int v : held) {
      predictions_.col(v) = positions_.col(v);
      impulses_.col(v).setZero();
      attachment_lambdas_.col(v).setZero();
      if (holds_[static_cast<std::size_t>(v)] == Hold::kExact) {
        positions_.col(v) = place(v, positions_.col(v), s, n);
      }
    }
    std::fill(multipliers_.begin(), multipliers_.end(), Eigen::Vector2d::Zero());

    for (int iteration = 0; iteration < params_.iterations; ++iteration) {
      sweep_tets(deviatoric_compliance_, hydrostatic_compliance_);
      for (const int v : held) {
        if (holds_[static_cast<std::size_t>(v)] == Hold::kExact) {
          positions_.col(v) = place(v, positions_.col(v), s, n);
          continue;
        }
        // A compliant attachment C = held (x - target), compliance 1 / k: its gradient is the
        // projector, so dlambda (3 numbers) stays in the held directions.
        const PositionConstraint* const attachment = constraints_.of(v);
        if (attachment == nullptr || !(attachment->stiffness > 0.0)) {
          continue;
        }
        const PositionConstraint& constraint = *attachment;
        const double w = inverse_masses_[v];
        const double alpha = 1.0 / (constraint.stiffness * h2);
        const Eigen::Vector3d gap = constraint.held * (positions_.col(v) - constraint.target);
        const Eigen::Vector3d change = -(gap + alpha * attachment_lambdas_.col(v)) / (w + alpha);
        positions_.col(v) += w * change;
        attachment_lambdas_.col(v) += change;
      }
    }

    velocities_ = (positions_ - previous_) / h;
    // Momentum balance at each held vertex: what moved it beyond its prediction and the tets'
    // impulses is the hold.
    for (const int v : held) {
      const PositionConstraint& constraint = *constraints_.of(v);
      constraint_forces_.col(v) +=
          constraint.held
          * ((masses_[v] * (positions_.col(v) - predictions_.col(v)) - impulses_.col(v)) / h2);
    }
    if (!positions_.allFinite()) {
      stats.finite = false;
      break;
    }
  }
  constraint_forces_ /= static_cast<double>(substeps);

  for (const int v : constraints_.exact_vertices()) {
    const PositionConstraint& constraint = *constraints_.of(v);
    stats.max_constraint_error =
        std::max(stats.max_constraint_error, constraint.gap(positions_.col(v)).norm());
  }
  unbind();
  stats.iterations = substeps * params_.iterations;
  stats.residual = residual();
  stats.finite = stats.finite && std::isfinite(stats.residual) && all_finite(velocities_);
  return stats;
}

}  // namespace softbench::xpbd
