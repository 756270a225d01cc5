// SPDX-License-Identifier: MIT
// One step of the corotational FEM: rotations, element terms, gather into the fixed pattern,
// exact constraints by elimination, one linear solve, update and reactions.
#include "models/corotational_fem/corotational_fem_model.h"
#include "models/phase_clock.h"

#include <algorithm>
#include <cstddef>
#include <cstring>

namespace softbench::corotational_fem {
namespace {

/// Four doubles in one vector (an AVX register at x86-64-v3, two SSE2 ones at the baseline).
/// The gathers sum 3x3 outer products w_a w_b^T column by column: a column is w_a times one
/// entry of w_b, three multiply-adds of a vector an incidence where Eigen's 3x3 product made
/// nine scalar ones and a separate dot product (now the trace). Measured on the liver: 6-10%
/// less time a step. (Prefetching the columns some incidences ahead, which had saved 5-7% of
/// the scalar gathers before the vertices were renumbered, then cost 7%: not kept.)
using Quad = double __attribute__((vector_size(4 * sizeof(double))));

/// Column `a` of an element's terms into lanes 0-2 of `column`, lane 3 whatever follows it (the
/// next column's first entry, or the padding element's: the term arrays have one element more
/// than the mesh, so the load never leaves them). An output argument: a 32-byte vector returned
/// by value has another ABI at the baseline level (GCC's -Wpsabi).
[[gnu::always_inline]] inline void load_column(const Matrix34d& terms, int a, Quad& column) {
  std::memcpy(&column, terms.col(a).data(), sizeof column);
}

/// The 3x3 matrix whose column j is lanes 0-2 of column<j>.
[[gnu::always_inline]] inline Eigen::Matrix3d to_matrix(const Quad& column0,
                                                        const Quad& column1,
                                                        const Quad& column2) {
  Eigen::Matrix3d m;
  m << column0[0], column1[0], column2[0], column0[1], column1[1], column2[1], column0[2],
      column1[2], column2[2];
  return m;
}

/// A gather's sums over the incidences [begin, end): add(k, sums) adds incidence k into `sums`
/// (a struct of vectors with +=). The incidences go alternately into two sets of sums, added at
/// the end: each set's chain of dependent multiply-adds is half as long, and that latency, not
/// the loads, bounded the loops (15-20% less time for the liver's gathers).
template <class Sums, class Add>
[[gnu::always_inline]] inline Sums sum_in_two_chains(int begin, int end, const Add& add) {
  Sums even{};
  Sums odd{};
  int k = begin;
  for (; k + 2 <= end; k += 2) {
    add(k, even);
    add(k + 1, odd);
  }
  if (k < end) {
    add(k, even);
  }
  even += odd;
  return even;
}

/// Column j of a sum of 3x3 outer products in lanes 0-2 of column<j>.
struct OuterSums {
  Quad column0{};
  Quad column1{};
  Quad column2{};
  OuterSums& operator+=(const OuterSums& other) {
    column0 += other.column0;
    column1 += other.column1;
    column2 += other.column2;
    return *this;
  }
  Eigen::Matrix3d matrix() const { return to_matrix(column0, column1, column2); }
};

/// A vertex's sums: its diagonal block's outer products and its right-hand side's terms.
struct VertexSums {
  OuterSums outer;
  Quad rhs{};
  VertexSums& operator+=(const VertexSums& other) {
    outer += other.outer;
    rhs += other.rhs;
    return *this;
  }
};

}  // namespace

void CorotationalFemModel::assemble(double mass_coefficient,
                                    double stiffness_coefficient,
                                    double dt,
                                    const StepInput& input) {
  const double lambda = lame_.lambda;
  const double mu = lame_.mu;
  const double mass_damping = params_.rayleigh_mass;
#pragma omp parallel for schedule(static) if (threaded())
  for (int v = 0; v < num_vertices_; ++v) {
    const VertexSums sums = sum_in_two_chains<VertexSums>(
        vertex_offsets_[static_cast<std::size_t>(v)],
        vertex_offsets_[static_cast<std::size_t>(v) + 1], [this](int k, VertexSums& into) {
          const int incidence = vertex_incidences_[static_cast<std::size_t>(k)];
          const auto e = static_cast<std::size_t>(incidence / 4);
          const int a = incidence % 4;
          const Matrix34d& w = element_gradients_[e];
          Quad wa;
          load_column(w, a, wa);
          into.outer.column0 += wa * w(0, a);
          into.outer.column1 += wa * w(1, a);
          into.outer.column2 += wa * w(2, a);
          Quad rhs_part;
          load_column(element_rhs_[e], a, rhs_part);
          into.rhs += rhs_part;
        });
    const Quad& rhs = sums.rhs;
    const Eigen::Matrix3d outer = sums.outer.matrix();
    const double inner = outer.trace();  // sum |w|^2
    // sum_e K_aa = (lambda + mu) sum w w^T + mu sum |w|^2 I.
    Eigen::Matrix3d block = (stiffness_coefficient * (lambda + mu)) * outer;
    const double mass = masses_(v);
    block.diagonal().array() += stiffness_coefficient * mu * inner + mass_coefficient * mass;
    Eigen::Vector3d force = mass * (input.gravity - mass_damping * velocities_.col(v));
    if (input.external_forces != nullptr) {
      force += input.external_forces->col(v);
    }
    const PositionConstraint* constraint = constraints_.of(v);
    if (is_penalty(constraint)) {
      // A spring k H (target - x), H the held directions: its stiffness k H adds dt^2 k H to A
      // and -dt^2 k H v to b.
      block += (dt * dt * constraint->stiffness) * constraint->held;
      force += constraint->stiffness * constraint->gap(positions_.col(v) + dt * velocities_.col(v));
    }
    pattern_->set(pattern_->vertex_block(v), block);
    rhs_.segment<3>(3 * v) = Eigen::Vector3d(rhs[0], rhs[1], rhs[2]) + dt * force;
  }
  const auto num_edges = static_cast<int>(edge_offsets_.size()) - 1;
#pragma omp parallel for schedule(static) if (threaded())
  for (int edge = 0; edge < num_edges; ++edge) {
    // sum over the edge's elements of w_a w_b^T, a and b its two vertices' places in each.
    const OuterSums sums = sum_in_two_chains<OuterSums>(
        edge_offsets_[static_cast<std::size_t>(edge)],
        edge_offsets_[static_cast<std::size_t>(edge) + 1], [this](int k, OuterSums& into) {
          const int incidence = edge_incidences_[static_cast<std::size_t>(k)];
          const Matrix34d& w = element_gradients_[static_cast<std::size_t>(incidence / 16)];
          Quad wa;
          load_column(w, (incidence / 4) % 4, wa);
          const int b = incidence % 4;
          into.column0 += wa * w(0, b);
          into.column1 += wa * w(1, b);
          into.column2 += wa * w(2, b);
        });
    const Eigen::Matrix3d outer = sums.matrix();
    const double inner = outer.trace();  // sum w_a . w_b
    // sum_e K_ab = lambda sum w_a w_b^T + mu (sum w_a w_b^T)^T + mu sum (w_a . w_b) I.
    Eigen::Matrix3d block = lambda * outer + mu * outer.transpose();
    block.diagonal().array() += mu * inner;
    block *= stiffness_coefficient;
    pattern_->set(pattern_->edge_block(edge), block);
    pattern_->set(pattern_->edge_block_transposed(edge), block.transpose());
  }
}

void CorotationalFemModel::eliminate_exact_constraints(double dt) {
  exact_velocity_changes(constraints_, positions_, velocities_, dt, known_changes_);
  elimination_.eliminate(*pattern_, constraints_, known_changes_, rhs_, velocity_change_);
}

void CorotationalFemModel::compute_reactions(double dt) {
  implicit_reactions(elimination_, *pattern_, constraints_, positions_, velocity_change_, dt,
                     constraint_forces_);
  // Published at the constrained vertices only (zero elsewhere): mapping all of the liver's
  // columns at every read took a few of the contact's 150 microseconds a touching step.
  for (const int outer : published_vertices_) {
    published_forces_.col(outer).setZero();
  }
  published_vertices_.clear();
  for (const int v : constraints_.vertices()) {
    const int outer = renumbering_.to_outer(v);
    published_forces_.col(outer) = constraint_forces_.col(v);
    published_vertices_.push_back(outer);  // allocates only when the constrained set grows
  }
}

StepStats CorotationalFemModel::step_timed(double dt,
                                           const StepInput& outer_input,
                                           PhaseTimes* times) {
  const ThreadChoice::Scope threads(thread_choice_);
  PhaseClock clock(times);
  const StepInput input = renumbering_.to_inner(outer_input);
  constraints_.bind(input.constraints);
  deform_and_compute_terms({.velocity_weight = params_.rayleigh_stiffness + dt, .force_scale = dt});
  clock.lap(&PhaseTimes::elements);

  assemble(1.0 + dt * params_.rayleigh_mass, dt * (params_.rayleigh_stiffness + dt), dt, input);
  eliminate_exact_constraints(dt);
  clock.lap(&PhaseTimes::assembly);

  solver_->set_energy_floor(resting_energy(total_mass_, rest_size_, dt));
  const SolveReport report =
      solver_->solve(*pattern_, rhs_, velocity_change_, elimination_.in_frame(velocities_));
  elimination_.to_world(velocity_change_);
  clock.lap(&PhaseTimes::solve);

  apply_velocity_change(constraints_, dt, velocity_change_, positions_, velocities_);
  compute_reactions(dt);
  renumbering_.publish(positions_, velocities_);

  StepStats stats = finish_step();
  constraints_.unbind();
  stats.iterations = report.iterations;
  stats.residual = report.residual;
  stats.factorizations = report.factorizations;
  stats.linear_solves = 1;
  stats.truncated_solves = report.converged ? 0 : 1;
  stats.finite = stats.finite && report.succeeded;
  clock.lap(&PhaseTimes::update);
  return stats;
}

StepStats CorotationalFemModel::finish_step() const {
  StepStats stats;
  for (const int v : constraints_.vertices()) {
    const PositionConstraint* constraint = constraints_.of(v);
    if (is_penalty(constraint)) {
      stats.max_constraint_error =
          std::max(stats.max_constraint_error, constraint->gap(positions_.col(v)).norm());
    }
  }
  stats.finite = positions_.allFinite() && velocities_.allFinite();
  return stats;
}

}  // namespace softbench::corotational_fem
