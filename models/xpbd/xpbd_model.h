// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/neo_hookean/stable_neo_hookean.h"
#include "models/param_table.h"
#include "models/vertex_constraints.h"
#include "models/xpbd/xpbd.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include <cstdint>
#include <string>
#include <vector>

namespace softbench::xpbd {

/// The most substeps a step takes, however stiff the material (a bound on a step's work), and
/// the `substeps` parameter's upper limit.
inline constexpr int kMaxSubsteps = 100000;

/// The parameter table: reads scene blocks, echoes effective values, documents defaults.
const ParamTable<XpbdParams>& param_table();

/// Throws InputError naming `where` for a value the table would reject.
void validate(const XpbdParams& params, const std::string& where);

/// The model of xpbd.h. Construction precomputes per tet its rest inverse and volume, per
/// vertex its mass and the tets around it; a step allocates nothing.
class XpbdModel final : public SoftBody {
 public:
  XpbdModel(const TetMesh& mesh, const Material& material, const XpbdParams& params);

  std::string_view name() const override { return "xpbd"; }
  nlohmann::json parameters() const override;
  StepStats step(double dt, const StepInput& input) override;
  void reset() override;

  const Eigen::Matrix3Xd& positions() const override { return positions_; }
  const Eigen::Matrix3Xd& velocities() const override { return velocities_; }
  /// Nothing is kept that depends on the velocities (lambda restarts every substep).
  void set_velocities(const Eigen::Matrix3Xd& velocities) override;
  void set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) override;
  const Eigen::Matrix3Xd& constraint_forces() const override { return constraint_forces_; }
  double elastic_energy() const override;
  std::size_t memory_bytes() const override;

  /// One Gauss-Seidel sweep over the tets at the current positions, as a substep of length h
  /// makes it with nothing held (for benchmarks: the step's inner loop alone). Moves the body.
  void sweep(double substep);
  /// The residual a step reports (xpbd.h), at the current positions and multipliers.
  double residual() const;
  int num_tets() const { return static_cast<int>(tets_.size()); }
  /// The substeps a step of dt takes: `substeps`, or more where the material and the smallest
  /// elements need them to stay stable (XpbdParams::stability_ratio).
  int substeps_for(double dt) const;
  /// sqrt(mu max_t V_t sum_a |grad N_a|^2 / m_a), 1/s: the rate of the stiffest tet's shear.
  double stability_rate() const { return stability_rate_; }

 private:
  /// What the sweep reads of a tet (80 bytes): S = Dm^-1 Dm^-T (symmetric: S00, S11, S22, S01,
  /// S02, S12; 1/m^2), det Dm^-1 = 1 / (6 V), 1 / V and its vertices (project_tet says why).
  struct Tet {
    double metric[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    double det_rest_inverse = 0.0;
    double inverse_volume = 0.0;
    int vertices[4] = {0, 0, 0, 0};
  };
  /// Per vertex, during a step: how it is held.
  enum class Hold : std::uint8_t { kFree, kExact, kPenalty };

  /// One sweep: every tet's two constraints, with the compliances over h^2 given.
  void sweep_tets(double deviatoric_compliance, double hydrostatic_compliance);
  /// Projects tet t; `general`: some vertex is held (matrix inverse masses, impulses recorded).
  template <bool kGeneral>
  void project_tet(std::size_t t, double deviatoric_compliance, double hydrostatic_compliance);
  /// Projects tets t and t + 1 together (they share no vertex, none held).
  void project_pair(std::size_t t, double deviatoric_compliance, double hydrostatic_compliance);
  void bind(const StepInput& input);
  void unbind();
  /// F of tet t (sweep order) at the current positions.
  Eigen::Matrix3d deformation(std::size_t t) const;
  /// Where exact hold `vertex` is put in substep `s` of `n` (1-based), from `x`.
  Eigen::Vector3d place(int vertex, const Eigen::Vector3d& x, int s, int n) const;

  XpbdParams params_;
  neo_hookean::StableNeoHookean law_;  ///< the reference's energy, the same parameters
  int num_vertices_ = 0;

  std::vector<Tet> tets_;
  std::vector<Eigen::Matrix3d> rest_inverses_;  ///< Dm^-1 per tet (energy, residual)
  double stability_rate_ = 0.0;                 ///< stability_rate()
  Eigen::VectorXd masses_;
  Eigen::VectorXd inverse_masses_;
  Eigen::Matrix3Xd rest_positions_;
  // The tets around each vertex (CSR): what a hold marks.
  std::vector<int> vertex_offsets_;
  std::vector<int> vertex_tets_;
  /// Per tet: 1 if it shares no vertex with the next (the sweep may project them together).
  std::vector<std::uint8_t> paired_;

  // State.
  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xd velocities_;
  Eigen::Matrix3Xd constraint_forces_;
  std::vector<Eigen::Vector2d> multipliers_;  ///< lambda_D, lambda_H per tet, this substep

  // Per-step work arrays, sized once.
  VertexConstraints constraints_;
  std::vector<Hold> holds_;                ///< per vertex
  std::vector<std::uint8_t> general_;      ///< per tet: touches a held vertex
  std::vector<Eigen::Matrix3d> mobility_;  ///< per held vertex: W = (I - held) / m, or I / m
  Eigen::Matrix3Xd starts_;                ///< per held vertex: where the step started
  Eigen::Matrix3Xd predictions_;           ///< per held vertex: x~ of this substep
  Eigen::Matrix3Xd impulses_;              ///< per held vertex: the tets' sum g dlambda
  Eigen::Matrix3Xd attachment_lambdas_;    ///< per penalty vertex
  Eigen::Matrix3Xd previous_;              ///< x at the start of the substep
  /// The last substep's alpha~ V: 1 / (mu h^2) and 1 / (lambda h^2) (residual()).
  double deviatoric_compliance_ = 0.0;
  double hydrostatic_compliance_ = 0.0;
};

}  // namespace softbench::xpbd
