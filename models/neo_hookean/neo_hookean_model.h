// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/block_pattern.h"
#include "models/implicit_system.h"
#include "models/neo_hookean/neo_hookean.h"
#include "models/neo_hookean/stable_neo_hookean.h"
#include "models/neo_hookean/tet_kinematics.h"
#include "models/param_table.h"
#include "models/system_solver.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <string>
#include <vector>

namespace softbench::neo_hookean {

/// The parameter table: reads scene blocks, echoes effective values, documents defaults.
const ParamTable<NeoHookeanParams>& param_table();

/// Throws InputError naming `where` for a value the table would reject.
void validate(const NeoHookeanParams& params, const std::string& where);

/// The model of neo_hookean.h. Construction precomputes the elements, the matrix pattern, each
/// element's 16 block positions in it and CHOLMOD's symbolic analysis.
///
/// A Newton iteration: (1) per element, F, V Psi, the gradient and the projected 12x12 Hessian
/// (parallel over elements above kParallelElements, into per-element storage); (2) a serial
/// scatter into the gradient and the fixed pattern, in element order (results do not depend on
/// the thread count); (3) exact constraints eliminated; (4) CHOLMOD; (5) the line search, whose
/// trials need only element energies.
class NeoHookeanModel final : public SoftBody {
 public:
  NeoHookeanModel(const TetMesh& mesh, const Material& material, const NeoHookeanParams& params);

  std::string_view name() const override { return "neo_hookean"; }
  nlohmann::json parameters() const override;
  StepStats step(double dt, const StepInput& input) override;
  void reset() override;

  const Eigen::Matrix3Xd& positions() const override { return positions_; }
  const Eigen::Matrix3Xd& velocities() const override { return velocities_; }
  /// A step predicts x + dt v from them and keeps no other velocity state.
  void set_velocities(const Eigen::Matrix3Xd& velocities) override;
  void set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) override;
  const Eigen::Matrix3Xd& constraint_forces() const override { return constraint_forces_; }
  /// sum_e V_e Psi(F_e) at the current positions, J (zero at rest and for rigid motions).
  double elastic_energy() const override;
  std::size_t memory_bytes() const override;

  // For tests.

  /// d(elastic_energy)/dx at the current positions (3 x #V, N): the negated elastic forces.
  Eigen::Matrix3Xd elastic_gradient();
  /// d^2(elastic_energy)/dx^2 (3#V x 3#V, N/m), element Hessians projected to PSD or not,
  /// assembled through the step's pattern (overwrites the system matrix).
  Eigen::SparseMatrix<double> elastic_hessian(bool projected);
  /// The energy's parameters (from the material's E and nu).

 private:
  /// The coefficients of one step's incremental potential.
  struct Potential {
    double dt = 0.0;
    double mass_coefficient = 0.0;  ///< 1/dt^2 + alpha/dt: M's factor in the Hessian
    const StepInput* input = nullptr;
  };

  /// What evaluate_elements() computes besides the energies.
  enum class Derivatives { kNone, kGradient, kGradientAndHessian, kGradientAndProjectedHessian };

  /// Per element at `x` (3 x #V): V Psi into element_energies_ and, as asked, the gradient into
  /// element_gradients_ and the Hessian into element_hessians_.
  void evaluate_elements(const Eigen::Matrix3Xd& x, Derivatives derivatives);
  /// E(x) and the sum of its terms' magnitudes (J): the scale of its round-off.
  struct EnergyValue {
    double value = 0.0;
    double magnitude = 0.0;
  };
  /// E(x), with the element energies of the last evaluate_elements(x, ...).
  EnergyValue potential_energy(const Potential& potential, const Eigen::Matrix3Xd& x) const;
  /// gradient_ = dE/dx at x from the element terms (3 x #V, N).
  void assemble_gradient(const Potential& potential, const Eigen::Matrix3Xd& x);
  /// The pattern's values = d^2E/dx^2 from the element Hessians.
  void assemble_hessian(const Potential& potential);

  NeoHookeanParams params_;
  StableNeoHookean law_;
  int num_vertices_ = 0;
  int num_elements_ = 0;
  double length_scale_ = 1.0;  ///< m, the rest bounding-box diagonal

  // Mesh and elements, fixed after construction.
  Eigen::Matrix4Xi tets_;
  Eigen::VectorXd masses_;
  Eigen::Matrix3Xd rest_positions_;
  std::vector<TetRest> elements_;
  /// Per element, 16 blocks: entries of block (row node a, column node b) at 4 a + b.
  std::vector<BlockEntries> element_blocks_;

  // State.
  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xd velocities_;
  Eigen::Matrix3Xd constraint_forces_;

  // Per-step work arrays, sized once.
  std::vector<double> element_energies_;
  std::vector<Matrix34d> element_gradients_;
  std::vector<Matrix12d> element_hessians_;
  VertexConstraints constraints_;
  std::unique_ptr<BlockPattern> pattern_;
  std::unique_ptr<SystemSolver> solver_;
  ConstraintElimination elimination_;
  Eigen::Matrix3Xd previous_;     ///< x_n
  Eigen::Matrix3Xd predicted_;    ///< x_n + dt v_n
  Eigen::Matrix3Xd trial_;        ///< line-search positions
  Eigen::Matrix3Xd gradient_;     ///< dE/dx
  Eigen::Matrix3Xd zero_change_;  ///< the Newton step at exact vertices: zero
  Eigen::VectorXd rhs_;           ///< -dE/dx, 3#V
  Eigen::VectorXd newton_step_;   ///< dx, 3#V
};

}  // namespace softbench::neo_hookean
