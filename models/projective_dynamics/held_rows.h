// SPDX-License-Identifier: MIT
#pragma once

#include "models/cholmod_factor.h"
#include "models/soft_body.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cstddef>
#include <span>
#include <vector>

namespace softbench::projective_dynamics {

/// Holds imposed on a kept factor by Lagrange multipliers. The global step solves
///     A x = b + sum_r n_r lambda_r e_{v(r)}   with   n_r . x_{v(r)} = d_r - c_r lambda_r
/// for rows r (a held vertex v(r), a unit direction n_r, the target along it d_r, a compliance
/// c_r: 0 for an exact hold, 1/k for a penalty spring). A is the same scalar matrix for the
/// three coordinates, so x = A^-1 b + sum_r z_{v(r)} n_r^T lambda_r with z_v = A^-1 e_v, and
///     (S + C) lambda = d - (n_r . (A^-1 b)_{v(r)}),   S_qr = z_{v(r)}[v(q)] (n_q . n_r).
/// lambda_r is the force (N) the hold exerts along n_r.
///
/// The columns z_v cost one solve each (several in one multi-column solve) and are kept while
/// the factor lasts, so a contact that stays pays for its vertices once; the rows x rows system
/// is rebuilt each step (its directions, a contact's normals, change). Memory: at most
/// max(kMinKeptColumns, 2 x the step's held vertices) columns are kept; past that, only the
/// step's own (a contact patch moves by a few vertices a step, so few are solved again).
class HeldRows {
 public:
  explicit HeldRows(int num_vertices);

  /// The factor changed: every kept column is stale.
  void forget();
  /// The step's rows from its holds (held directions: the eigenvectors of `held` with
  /// eigenvalue 1); computes the missing columns with `factor`, and factorises S + C.
  /// Returns the number of columns solved for.
  int prepare(std::span<const PositionConstraint* const> holds, CholmodFactor& factor);
  /// Corrects the unconstrained move `move` (#V x 3, column-major, the global step's layout)
  /// from the positions `base` so that every row holds at base + move; keeps the multipliers.
  void correct(Eigen::MatrixX3d& move, const Eigen::Matrix3Xd& base);
  /// Adds each hold's force to its vertex's column of `forces` (N): an exact hold's
  /// multipliers sum_r n_r lambda_r from the last correct(), a penalty hold's spring force
  /// k held (target - x) at the final `positions` (which an accelerated iteration may have
  /// moved past the last solve).
  void add_forces(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd& forces) const;
  bool empty() const { return rows_.empty(); }
  std::size_t memory_bytes() const;

  static constexpr int kMinKeptColumns = 256;

 private:
  struct Row {
    int vertex;
    int column;  ///< into columns_
    Eigen::Vector3d direction;
    double target;
    double compliance;
  };
  int column_of(int vertex) const { return slot_[static_cast<std::size_t>(vertex)]; }

  int num_vertices_;
  std::vector<Row> rows_;
  std::vector<int> slot_;          ///< per vertex: its kept column, or -1
  std::vector<int> slot_vertex_;   ///< per kept column: its vertex
  std::vector<long> slot_step_;    ///< per kept column: the last step that used it
  Eigen::MatrixXd columns_;        ///< #V x capacity; the first kept hold z_v = A^-1 e_v
  long step_ = 0;
  Eigen::MatrixXd system_;         ///< S + C
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd multipliers_;
  Eigen::VectorXd gaps_;
  std::vector<int> missing_;
  Eigen::MatrixXd unit_rhs_;
};

}  // namespace softbench::projective_dynamics
