// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/block_pattern.h"
#include "models/corotational_fem/corotational_fem.h"
#include "models/corotational_fem/tet_element.h"
#include "models/implicit_system.h"
#include "models/param_table.h"
#include "models/renumbered_vertices.h"
#include "models/system_solver.h"
#include "models/thread_choice.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include <memory>
#include <string>
#include <vector>

namespace softbench::corotational_fem {

/// The parameter table: reads scene blocks, echoes effective values, documents defaults.
const ParamTable<CorotationalFemParams>& param_table();

/// Throws InputError naming `where` for a value the table would reject.
void validate(const CorotationalFemParams& params, const std::string& where);

/// Wall time of the phases of step(), accumulated over the steps that were given it (s).
struct PhaseTimes {
  double elements = 0.0;  ///< per element: F, R, the right-hand side part and w_a
  double assembly = 0.0;  ///< gather into A and b, elimination
  double solve = 0.0;     ///< the linear solve
  double update = 0.0;    ///< positions, velocities, reactions
};

/// The model of corotational_fem.h. Construction precomputes the elements, the vertex and edge
/// incidences and the matrix pattern; a step allocates nothing (CHOLMOD's numeric factorisation,
/// when used, makes ~10 small mallocs of its own per call).
///
/// A step: (1) per batch of elements side by side in vector lanes, F, R, the right-hand side
/// part and the rotated, volume-scaled gradients w_a = sqrt(V) R b_a (parallel over batches,
/// the last two into per-element storage); (2) per vertex and per edge, A's blocks and b gathered
/// from the incident elements in a fixed order (parallel, no atomics; the block sums are
/// lambda S + mu S^T + mu s I with S = sum w_a w_b^T, s = sum w_a . w_b); (3) exact constraints
/// eliminated; (4) one solve; (5) the update. Results do not depend on the thread count.
class CorotationalFemModel final : public SoftBody {
 public:
  CorotationalFemModel(const TetMesh& mesh,
                       const Material& material,
                       const CorotationalFemParams& params);

  /// From this many vertices the step's loops (elements, gathers, products, sweeps) run on the
  /// OpenMP threads (BlockPattern::threaded()) when ThreadChoice finds them faster, step by step;
  /// fewer run on one thread. The vertices are then numbered in kSweepParts parts and a
  /// separator (renumbered_for_locality()), so that the SSOR solver's sweeps run on the parts
  /// side by side. A fixed count, not the thread count: the numbering, and so every result, is
  /// the same on any number of threads. Measured on the 2-core test machine, idle: liver_x4
  /// (4091 vertices) 1.48x and liver_x16 1.5-2.05x on two threads. The shipped liver (1215
  /// vertices, 4777 tets) gained 1.6x when its step took 1.6 ms on one thread; at 1.0 ms it
  /// gains nothing (two threads 1.05-1.09 ms against 1.00-1.04 on one in the same process,
  /// ThreadChoice's probes included), so it stays below the bound, on one thread and numbered
  /// as one part (closer to CHOLMOD: 0.015% against 0.017%). When another process holds a core,
  /// every parallel region waits for the thread the scheduler has set aside (a step took 2-60
  /// times as long): ThreadChoice then runs one thread, and tries the threads only when a core
  /// is free.
  static constexpr int kThreadedVertices = 2048;
  static constexpr int kSweepParts = 2;
  /// The SSOR solve's coarse level when coarse_vertices is 0: from kCoarseFromVertices vertices,
  /// aggregates of kAggregateVertices, below it the whole body as one aggregate. Measured with
  /// fem_bench's cg+coarse_* variants (one thread, the same run): on liver_x16 aggregates of 64
  /// took the iterations from 14.4 to 8.7 a step and the step from 53 to 41 ms (32: 7.8
  /// iterations, but E's factorisation grows; 128: 9.4); on liver_x4 the time stayed (5.7 ms,
  /// 8.7 -> 6.6 iterations); on the shipped liver (1215 vertices, 4.7 iterations) no aggregate
  /// size saved an iteration's cost. In every case cholmod_match fell 10-25 fold (liver_x16
  /// 0.041% -> 0.0020%).
  static constexpr int kCoarseFromVertices = 2048;
  static constexpr int kAggregateVertices = 64;
  /// The SSOR sweeps read the matrix in single precision from this many vertices
  /// (sweep_precision "auto"): measured with fem_bench's cg+single_sweeps and cg+double_sweeps
  /// variants (see there).
  static constexpr int kSingleSweepsFromVertices = 2048;
  /// Elements side by side in the element kernels, one per vector lane.
  static constexpr int kElementLanes = 8;
  /// A 3x3 matrix of each lane: column-major entries, m[i + 3 j][lane] is entry (i, j).
  using Lanes3x3 = double[9][kElementLanes];
  /// Lane `lane` of `lanes` as a matrix, and a matrix into it.
  static Eigen::Matrix3d lane_of(const Lanes3x3& lanes, int lane) {
    Eigen::Matrix3d m;
    for (int k = 0; k < 9; ++k) {
      m.data()[k] = lanes[k][lane];
    }
    return m;
  }
  static void set_lane(Lanes3x3& lanes, int lane, const Eigen::Matrix3d& m) {
    for (int k = 0; k < 9; ++k) {
      lanes[k][lane] = m.data()[k];
    }
  }

  std::string_view name() const override { return "corotational_fem"; }
  nlohmann::json parameters() const override;
  StepStats step(double dt, const StepInput& input) override { return step_timed(dt, input); }
  void reset() override;

  const Eigen::Matrix3Xd& positions() const override { return renumbering_.positions(); }
  const Eigen::Matrix3Xd& velocities() const override { return renumbering_.velocities(); }
  /// Also drops the solve's warm start (the last dv, made for the old velocities); the element
  /// rotations' warm starts depend on the positions only and are kept.
  void set_velocities(const Eigen::Matrix3Xd& velocities) override;
  void set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) override;
  /// In the mesh's numbering (published by each step).
  const Eigen::Matrix3Xd& constraint_forces() const override { return published_forces_; }
  /// At the current positions, with the exact polar rotation (SVD) whatever `rotation` is, so
  /// it is a function of the positions alone.
  double elastic_energy() const override;
  std::size_t memory_bytes() const override;

  /// step() that also adds each phase's wall time to `times` (for benchmarks; null: no timing).
  StepStats step_timed(double dt, const StepInput& input, PhaseTimes* times = nullptr);

  // The pieces of a step, for tests.

  /// F of every element at the current positions and, unless `hold_rotations`, its rotation R
  /// (holding R, that of the last call, is the warped-stiffness tangent's assumption), kept for
  /// the two pieces below. A step makes F and R batch by batch as it uses them and keeps only
  /// the rotations' warm starts.
  void update_deformations(bool hold_rotations = false);
  /// The elastic forces f(x) (3 x #V, N) with the F and R of the last update_deformations().
  Eigen::Matrix3Xd elastic_forces();
  /// K = -df/dx with the current rotations held fixed, assembled through the step's pattern and
  /// gather (3#V x 3#V, N/m). Overwrites the system matrix.
  Eigen::SparseMatrix<double> stiffness_matrix();

 private:
  CorotationalFemModel(RenumberedMesh inner,
                       const Material& material,
                       const CorotationalFemParams& params);

  /// What the element terms are made with: the right-hand-side part force_scale * f_a is
  /// evaluated at F + velocity_weight G (G the velocity gradient).
  struct TermScales {
    double velocity_weight = 0.0;
    double force_scale = 1.0;
  };
  /// Whether the step's loops may run on the threads (kThreadedVertices).
  bool threaded() const { return pattern_->threaded(); }
  /// A batch of kElementLanes elements side by side (corotational_fem_terms.cpp).
  struct ElementBatch;
  /// body(batch) for every batch, its rest data loaded (parallel when threaded()).
  template <class Body>
  void for_each_batch(const Body& body);
  /// The batch's F at the current positions and its R (see update_deformations()).
  void deform(ElementBatch& lanes, bool hold_rotations);
  /// The batch's right-hand-side parts and rotated gradients w_a from its F and R.
  void make_terms(ElementBatch& lanes, const TermScales& scales);
  /// The terms of every element from the F and R of the last update_deformations().
  void compute_element_terms(const TermScales& scales);
  /// A step's first phase: F, R and the terms of every element, batch by batch, F and R never
  /// leaving the batch. Measured on the liver against F and R for all elements first (two
  /// per-element arrays, 0.7 MB) and the terms in a second pass: 3% less time a step (30
  /// alternated runs), the element phases 23% of the step instead of 26%.
  void deform_and_compute_terms(const TermScales& scales);
  /// A = mass_coefficient M + stiffness_coefficient K (+ dt^2 k I at penalty constraints) and
  /// b = the element parts + dt (M g + f_ext + penalty forces) - dt (alpha M v + dt k v).
  void assemble(double mass_coefficient,
                double stiffness_coefficient,
                double dt,
                const StepInput& input);
  void eliminate_exact_constraints(double dt);
  void compute_reactions(double dt);
  StepStats finish_step() const;

  CorotationalFemParams params_;
  /// The model numbers the vertices by reverse Cuthill-McKee and its elements by their first
  /// vertex (renumbered_for_locality): a vertex's elements and neighbours then lie close in
  /// memory for the gathers and the solver's sweeps. Measured on the liver: 7% less CPU a step
  /// than in the file's order, 3% fewer iterations. Every member below is in that numbering but
  /// the published state.
  RenumberedVertices renumbering_;
  LameParameters lame_;
  int num_vertices_ = 0;
  int num_elements_ = 0;

  // Mesh and elements, fixed after construction.
  Eigen::Matrix4Xi tets_;
  Eigen::VectorXd masses_;
  Eigen::Matrix3Xd rest_positions_;
  double total_mass_ = 0.0;  ///< kg, and the rest bounding-box diagonal (m): the iterative
  double rest_size_ = 0.0;   ///< solve's floor at rest (resting_energy())
  /// The elements' rest data, kElementLanes elements side by side as the element kernels read
  /// it (Lanes3x3; unused lanes zero), and only so: kept in this layout rather than gathered
  /// from per-element matrices every step, 2% of the liver's step.
  struct RestBatch {
    alignas(64) Lanes3x3 rest_inverse;         ///< Dm^-1
    alignas(64) Lanes3x3 scaled_gradients;     ///< sqrt(V) [b1 b2 b3]: w_a = R these
    alignas(64) double volume[kElementLanes];  ///< V
  };
  std::vector<RestBatch> rest_batches_;
  /// Element t's rest data.
  TetRest rest_of(int t) const;
  // Incidences (CSR) for the gathers: per vertex, element * 4 + local index; per edge (i < j),
  // element * 16 + 4 * (local index of i) + (local index of j).
  std::vector<int> vertex_offsets_;
  std::vector<int> vertex_incidences_;
  std::vector<int> edge_offsets_;
  std::vector<int> edge_incidences_;

  // State.
  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xd velocities_;
  Eigen::Matrix3Xd constraint_forces_;  ///< in the model's numbering
  Eigen::Matrix3Xd published_forces_;   ///< the same in the mesh's (constraint_forces())
  /// The columns of published_forces_ the last step wrote (its constrained vertices, in the
  /// mesh's numbering): the forces are zero elsewhere.
  std::vector<int> published_vertices_;
  std::vector<Eigen::Quaterniond> quaternions_;  ///< warm starts (rotation "quaternion")

  // Per-step work arrays, sized once.
  std::vector<Eigen::Matrix3d> deformations_;  ///< F per element (update_deformations())
  std::vector<Eigen::Matrix3d> rotations_;     ///< R per element (I for "linear"; likewise)
  std::vector<Matrix34d> element_rhs_;         ///< per element, its nodes' right-hand side parts
  std::vector<Matrix34d> element_gradients_;   ///< per element, w_a = sqrt(V) R b_a
  VertexConstraints constraints_;
  std::unique_ptr<BlockPattern> pattern_;
  std::unique_ptr<SystemSolver> solver_;
  ConstraintElimination elimination_;
  Eigen::Matrix3Xd known_changes_;   ///< dv at exactly constrained vertices
  Eigen::VectorXd rhs_;              ///< b, 3#V
  Eigen::VectorXd velocity_change_;  ///< dv; the previous step's warm-starts CG
  /// One thread or the OpenMP threads, step by step, whichever is faster now: the results do
  /// not depend on it.
  ThreadChoice thread_choice_;
};

}  // namespace softbench::corotational_fem
