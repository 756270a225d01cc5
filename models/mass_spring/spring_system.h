// SPDX-License-Identifier: MIT
#pragma once

#include "models/system_solver.h"
#include "models/vertex_constraints.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <vector>

namespace softbench::mass_spring {

/// Backward Euler's system for springs between vertices, kept as per-spring coefficients rather
/// than a sparse matrix, and its preconditioned conjugate-gradient solve.
///
/// The matrix: A = M' + P + sum_e G_e^T B_e G_e, with M' the per-vertex scalar mass term, P the
/// penalty constraints' blocks (dt^2 k_p H, at a few vertices), G_e x = x_i - x_j and each
/// spring's block B_e = u_e u_e^T + s_e I (u_e = sqrt(along) d_e, s_e >= 0): every mass-spring
/// Jacobian block (dashpot and stiffness along the spring, the geometric term across it) has
/// this form. Stored per spring: 4 numbers, against 18 for its two blocks in a BlockPattern;
/// the liver's whole system (6802 springs) fits in the L2 cache, and a product A x is one pass
/// over the springs, (A x)_i += B_e (x_i - x_j), (A x)_j -= the same.
///
/// Exact constraints: the unknown u = dv at an exactly held vertex c is known along its held
/// directions H_c (PositionConstraint::held). The solve splits u = u_k + w, u_k the known part
/// and w in the free subspace (the filter S: I at a free vertex, 0 at a fully held one, I - H_c
/// at a sliding one), and solves S A S w = S (b - A u_k): the system ConstraintElimination makes
/// (identity rows for the known coordinates), in world coordinates instead of per-vertex frames.
/// Its stopping rule measures the same energy, |S (v + u)|^2_A + |H (v + u)|^2 with the caller's
/// offset v (EnergyErrorEstimate; LinearSolverOptions::tolerance).
///
/// Preconditioners (both built from the filtered system's 3x3 vertex blocks D_v and their
/// inverses):
/// - kSsor: symmetric Gauss-Seidel (SSOR with omega = 1: on the liver 1.2 saved 4% of the
///   iterations, 1.4 none), M = (D + L) D^-1 (D + U), applied with Eisenstat's trick (1981): CG
///   runs on (D + L)^-1 A (D + U)^-1 with the preconditioner D, so an iteration costs one
///   backward and one forward sweep over the springs (each about half a product) instead of a
///   product and two sweeps. Half the iterations of block Jacobi on the liver. The sweeps run in
///   vertex order, on one thread.
/// - kBlockJacobi: the inverse 3x3 vertex blocks; one product per iteration.
///
/// Warm start: the combination of the last kHistory solutions closest to this one in the energy
/// norm (their Galerkin projection: kHistory products, in one pass over the springs, and a
/// kHistory x kHistory solve). It is never worse than any one of them, so the stopping rule's
/// floor (the solve's own change) is no looser than with the last solution alone; where the
/// motion is smooth it is much better (a linear or higher extrapolation lies in the same span).
///
/// Nothing allocates after construction but the constraint lists, which grow to the largest set
/// seen. Every loop here runs on one thread in a fixed order: results do not depend on the
/// thread count.
class SpringSystem {
 public:
  enum class Preconditioner { kSsor, kBlockJacobi };

  /// `springs`: 2 x #S vertex pairs (i, j), i < j, sorted lexicographically (unique_edges'
  /// order): the springs each vertex owns (it is their first vertex) are contiguous.
  /// Throws std::invalid_argument otherwise.
  SpringSystem(int num_vertices, const Eigen::Matrix2Xi& springs);

  int num_vertices() const { return num_vertices_; }
  Eigen::Index num_springs() const { return static_cast<Eigen::Index>(others_.size()); }

  /// The springs incident to `vertex` (CSR, increasing spring index): [begin, end) of
  /// incident_springs().
  int incident_begin(int vertex) const {
    return incident_offsets_[static_cast<std::size_t>(vertex)];
  }
  int incident_end(int vertex) const {
    return incident_offsets_[static_cast<std::size_t>(vertex) + 1];
  }
  const std::vector<int>& incident_springs() const { return incident_springs_; }

  // -- Per step, in this order: bind(), every spring's block into spring_columns() and
  // -- set_vertex() for every vertex (each loop may run in parallel: every call writes its own
  // -- entries only), prepare().

  /// Which vertices are held exactly (the filter) or by a penalty spring, this step.
  void bind(const VertexConstraints& constraints);
  /// Where spring e's block B_e = u u^T + across I goes: ux[e], uy[e], uz[e], across[e] (one
  /// column each, so a loop can produce the springs several at a time).
  struct SpringColumns {
    double* ux;
    double* uy;
    double* uz;
    double* across;
  };
  SpringColumns spring_columns() {
    return {coefficients_.col(0).data(), coefficients_.col(1).data(), coefficients_.col(2).data(),
            coefficients_.col(3).data()};
  }
  /// Vertex v's own terms: the scalar mass term and, at a penalty vertex (bind()), its block
  /// (ignored elsewhere).
  void set_vertex(int v, double mass, const Eigen::Matrix3d& penalty);
  /// The vertex blocks D_v (own terms plus the springs'), filtered, and their inverses: one pass
  /// over the springs, on one thread.
  void prepare();

  /// Spring e's block.
  Eigen::Matrix3d spring_block(Eigen::Index e) const;
  /// Vertex v's diagonal block D_v, unfiltered.
  Eigen::Matrix3d vertex_block(int v) const;

  /// (A x)_v, unfiltered (the row of a constrained vertex as assembled: its reaction).
  Eigen::Vector3d row(int v, const Eigen::VectorXd& x) const;

  /// Solves A u = b under the bound exact constraints, u = `known` (3 x #V, read at exactly held
  /// vertices, along their held directions) there, into `x` (3 #V). The initial guess is the
  /// best the last kHistory solutions can make (warm_start()). `offset` (3 #V): what the stopping
  /// rule measures the error against (the velocities). The report's residual is that of the
  /// constrained system, |S (b - A u)| / |(S (b - A u_k), u_k)|; its error the estimate at the
  /// stop.
  SolveReport solve(const Eigen::VectorXd& b,
                    const Eigen::Matrix3Xd& known,
                    Eigen::VectorXd& x,
                    const Eigen::Matrix3Xd& offset,
                    Preconditioner preconditioner,
                    double tolerance,
                    int max_iterations);
  /// Drops the solutions kept for the warm start (made for other velocities).
  void forget_solutions();
  /// The least energy the stopping rule measures the error against, whatever the offset
  /// (resting_energy(); 0: none, the default).
  void set_energy_floor(double energy) { energy_floor_ = energy; }

  /// How many past solutions the warm start combines. Measured on the liver (defaults, at the
  /// default tolerance 1e-3): iterations per step 7.4 / 4.9 / 4.4 / 4.3 with 1 to 4 of them.
  /// Their products share one pass over the springs (multiply_history()). Even: the pass takes
  /// them two at a time.
  static constexpr int kHistory = 4;

  std::size_t memory_bytes() const;

 private:
  enum Kind : unsigned char { kFree, kFixed, kSliding };

  Eigen::Vector3d filter(int v, const Eigen::Vector3d& value) const;
  /// |y|^2_A for y in the free subspace.
  double energy(const double* y) const;

  /// w0 = the combination of the filtered past solutions s_j closest to the solution in the
  /// energy norm: G c = h with G_ij = s_i . A s_j, h_i = s_i . S (b - A u_k) (a Galerkin
  /// projection; no worse than any one of them, or their linear extrapolation). Into solution_,
  /// and its residual S (b - A u_k) - S A S w0 (from the same products) into residual_: the
  /// solves start from it.
  void warm_start();
  SolveReport solve_ssor(double tolerance, int max_iterations, double reference_energy);
  SolveReport solve_block_jacobi(double tolerance, int max_iterations, double reference_energy);

  /// sum = sum over the springs v owns (v = i) of B_e x_j.
  void owned_sum(int v, const double* x, double* sum) const;
  /// out_j += B_e y over the springs v owns.
  void push_owned(int v, const double* y, double* out) const;
  void filter_in_place(int v, double* value) const;
  /// visit(e, i, j) once for every spring e = (i, j) with a held end (both held: once).
  template <class Visit>
  void for_each_held_spring(const Visit& visit) const {
    for (const int c : held_vertices_) {
      for (int k = incident_begin(c); k < incident_end(c); ++k) {
        const int e = incident_springs_[static_cast<std::size_t>(k)];
        const int i = firsts_[static_cast<std::size_t>(e)];
        const int j = others_[static_cast<std::size_t>(e)];
        const int other = i + j - c;
        if (kinds_[static_cast<std::size_t>(other)] == kFree || other > c) {
          visit(static_cast<Eigen::Index>(e), i, j);
        }
      }
    }
  }
  /// S_v as a matrix: I at a free vertex, 0 at a fully held one, I - H at a sliding one
  /// (filter()'s columns, made once a step by bind()).
  const Eigen::Matrix3d& filter_matrix(int v) const {
    const int slot = slots_[static_cast<std::size_t>(v)];
    return kinds_[static_cast<std::size_t>(v)] == kFree
               ? kIdentity
               : held_filters_[static_cast<std::size_t>(slot)];
  }
  static inline const Eigen::Matrix3d kIdentity = Eigen::Matrix3d::Identity();
  /// The coarse correction on the rigid translations Z = S [e_x e_y e_z] that ends a solve:
  /// w += Z c with Z^T A Z c = Z^T r (the A-orthogonal projection, which never increases the
  /// error's energy norm), and the residual r updated. No stiffness resists a translation, so
  /// the sweeps leave its error nearly untouched, and an inexact solve breaks a free body's
  /// momentum balance by that much.
  void translation_correction(double* w, double* r) const;
  /// p = z + beta p, then t = (D + U)^-1 p, and g = p - D t.
  void backward_sweep(double beta);
  /// y = (D + L)^-1 g (g is consumed), q = t + y; returns p . q.
  double forward_sweep();
  /// out = S A S w for w in the free subspace; returns w . out.
  double filtered_multiply(const double* w, double* out) const;
  /// basis_products_ = S A S basis_: filtered_multiply() for every history vector in one pass.
  void multiply_history();

  int num_vertices_ = 0;
  // Springs by first vertex: vertex v owns [owned_offsets_[v], owned_offsets_[v + 1]).
  std::vector<int> owned_offsets_;
  std::vector<int> others_;  ///< per spring: its second vertex
  /// per spring: 3 x its second vertex, where its coordinates start (the sweeps' and products'
  /// gathers: one load instead of a load, a multiply and two address computations)
  std::vector<int> other_coordinates_;
  std::vector<int> firsts_;  ///< per spring: its first vertex
  std::vector<int> incident_offsets_;
  std::vector<int> incident_springs_;

  // Per step.
  /// Per spring (a row): u, across; by column, so the springs a vertex owns are four contiguous
  /// runs that its sweeps read as vectors.
  Eigen::Matrix<double, Eigen::Dynamic, 4> coefficients_;
  Eigen::VectorXd masses_;                             ///< the scalar mass term per vertex
  Eigen::Matrix<double, 6, Eigen::Dynamic> diagonal_;  ///< D_v (xx yy zz xy xz yz), unfiltered
  Eigen::Matrix<double, 6, Eigen::Dynamic> filtered_;  ///< S D_v S (D_v at a free vertex)
  Eigen::Matrix<double, 6, Eigen::Dynamic> inverse_;   ///< (S D_v S)^+: 0 at a fully held vertex
  std::vector<Kind> kinds_;
  std::vector<int> slots_;                     ///< per vertex: its entry in the lists below, or -1
  std::vector<int> held_vertices_;             ///< exactly held vertices, bind() order
  std::vector<Eigen::Matrix3d> held_;          ///< per held vertex: H (I at a fully held one)
  std::vector<Eigen::Matrix3d> held_filters_;  ///< per held vertex: S (filter_matrix())
  std::vector<int> penalty_vertices_;          ///< vertices held by a penalty spring
  std::vector<Eigen::Matrix3d> penalties_;     ///< per penalty vertex: its block

  // Work vectors (3 #V), sized once.
  Eigen::VectorXd rhs_;       ///< S (b - A u_k)
  Eigen::VectorXd known_;     ///< u_k
  Eigen::VectorXd solution_;  ///< w (the warm start's w0 until the solve ends)
  Eigen::VectorXd residual_;
  Eigen::VectorXd preconditioned_;
  Eigen::VectorXd direction_;
  Eigen::VectorXd product_;
  Eigen::VectorXd sweep_;        ///< SSOR: t of the backward sweep
  Eigen::VectorXd carry_;        ///< SSOR: g, consumed by the forward sweep
  Eigen::VectorXd transformed_;  ///< SSOR: x^ = (D + U) (w - w0) while iterating
  // The warm start. Its vectors are interleaved, kHistory values per coordinate (a vertex's
  // column: x of each, then y, then z), so that one pass over the springs multiplies them all:
  // the springs' coefficients and the other ends' values are read once, not once per vector.
  using History = Eigen::Matrix<double, 3 * kHistory, Eigen::Dynamic>;
  History history_;  ///< the last solutions, in ring slots (newest at history_head_; unused: 0)
  int history_head_ = 0;
  int history_count_ = 0;
  History basis_;              ///< per step: the history, filtered
  History basis_products_;     ///< S A S basis_
  double energy_floor_ = 0.0;  ///< set_energy_floor()
};

}  // namespace softbench::mass_spring
