// SPDX-License-Identifier: MIT
// The corotational FEM model: construction (all precomputation), state, energy, and the entry
// points tests use. The step is in corotational_fem_step.cpp, the parameters in
// corotational_fem_params.cpp.
#include "models/corotational_fem/corotational_fem.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "models/corotational_fem/corotational_fem_model.h"
#include "models/corotational_fem/polar_decomposition.h"
#include "models/memory_bytes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace softbench {
namespace corotational_fem {
namespace {

LinearSolverOptions solver_options(const CorotationalFemParams& params, int num_vertices) {
  LinearSolverOptions options;
  switch (params.solver) {
    case CorotationalFemParams::LinearSolver::kCholmod:
      options.kind = LinearSolverOptions::Kind::kCholmod;
      break;
    case CorotationalFemParams::LinearSolver::kConjugateGradient:
      options.kind = LinearSolverOptions::Kind::kConjugateGradient;
      break;
    case CorotationalFemParams::LinearSolver::kCholeskyPcg:
      options.kind = LinearSolverOptions::Kind::kCholeskyPcg;
      break;
  }
  options.preconditioner = params.preconditioner == CorotationalFemParams::Preconditioner::kSsor
                               ? LinearSolverOptions::Preconditioner::kSsor
                               : LinearSolverOptions::Preconditioner::kJacobi;
  options.coarse_vertices = params.coarse_vertices;
  if (options.coarse_vertices == 0 && num_vertices >= CorotationalFemModel::kCoarseFromVertices) {
    options.coarse_vertices = CorotationalFemModel::kAggregateVertices;
  }
  switch (params.sweep_precision) {
    case CorotationalFemParams::SweepPrecision::kAuto:
      options.single_precision_sweeps =
          num_vertices >= CorotationalFemModel::kSingleSweepsFromVertices;
      break;
    case CorotationalFemParams::SweepPrecision::kDouble:
      options.single_precision_sweeps = false;
      break;
    case CorotationalFemParams::SweepPrecision::kSingle:
      options.single_precision_sweeps = true;
      break;
  }
  options.projected_warm_start = params.projected_warm_start;
  options.tolerance = params.cg_tolerance;
  options.max_iterations = params.cg_max_iterations;
  options.refresh_iterations = params.refresh_iterations;
  return options;
}

}  // namespace

CorotationalFemModel::CorotationalFemModel(const TetMesh& mesh,
                                           const Material& material,
                                           const CorotationalFemParams& params)
    : CorotationalFemModel(
        renumbered_for_locality(mesh, mesh.num_vertices() >= kThreadedVertices ? kSweepParts : 1),
        material,
        params) {
}

CorotationalFemModel::CorotationalFemModel(RenumberedMesh inner,
                                           const Material& material,
                                           const CorotationalFemParams& params)
    : params_(params),
      renumbering_(std::move(inner.order)),
      lame_(lame_parameters(material)),
      num_vertices_(inner.mesh.num_vertices()),
      num_elements_(inner.mesh.num_tets()),
      tets_(inner.mesh.tets()),
      masses_(lumped_masses(inner.mesh, material.density)),
      rest_positions_(inner.mesh.rest_positions()),
      total_mass_(masses_.sum()),
      rest_size_(bounding_box_diagonal(rest_positions_)),
      constraints_(inner.mesh.num_vertices()) {
  const auto num_elements = static_cast<std::size_t>(num_elements_);
  rest_batches_.resize((num_elements + kElementLanes - 1) / kElementLanes, RestBatch{});
  for (int t = 0; t < num_elements_; ++t) {
    const TetRest rest = tet_rest(tet_positions(rest_positions_, tets_, t));
    RestBatch& batch = rest_batches_[static_cast<std::size_t>(t / kElementLanes)];
    const int lane = t % kElementLanes;
    set_lane(batch.rest_inverse, lane, rest.rest_inverse);
    set_lane(batch.scaled_gradients, lane, std::sqrt(rest.volume) * rest.rest_inverse.transpose());
    batch.volume[lane] = rest.volume;
  }

  // Vertex incidences, in element order.
  Incidences incidences = vertex_corners(tets_, num_vertices_);
  vertex_offsets_ = std::move(incidences.offsets);
  vertex_incidences_ = std::move(incidences.items);

  // Edge incidences, in element order; the edge's first (smaller) vertex's local index first.
  const Eigen::Matrix2Xi edges = unique_edges(tets_);
  constexpr std::array<std::pair<int, int>, 6> kTetEdges{
      {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
  std::vector<int> element_edges(6 * num_elements);
  std::vector<int> element_codes(6 * num_elements);
  for (int t = 0; t < num_elements_; ++t) {
    for (std::size_t k = 0; k < kTetEdges.size(); ++k) {
      auto [a, b] = kTetEdges[k];
      if (tets_(a, t) > tets_(b, t)) {
        std::swap(a, b);
      }
      const int edge = edge_index(edges, tets_(a, t), tets_(b, t));
      element_edges[6 * static_cast<std::size_t>(t) + k] = edge;
      element_codes[6 * static_cast<std::size_t>(t) + k] = 16 * t + 4 * a + b;
    }
  }
  Incidences by_edge = group_by_owner(element_edges, static_cast<int>(edges.cols()));
  edge_offsets_ = std::move(by_edge.offsets);
  edge_incidences_.reserve(by_edge.items.size());
  for (const int item : by_edge.items) {
    edge_incidences_.push_back(element_codes[static_cast<std::size_t>(item)]);
  }

  pattern_ = std::make_unique<BlockPattern>(num_vertices_, edges);
  pattern_->set_parts(std::move(inner.part_offsets));
  solver_ = make_system_solver(solver_options(params_, num_vertices_), *pattern_);

  deformations_.resize(num_elements);
  rotations_.resize(num_elements);
  quaternions_.resize(num_elements);
  // One element more than the mesh: the gathers load an element's last column with the double
  // after it (load_column in corotational_fem_step.cpp).
  element_rhs_.resize(num_elements + 1, Matrix34d::Zero());
  element_gradients_.resize(num_elements + 1, Matrix34d::Zero());
  known_changes_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  rhs_.resize(pattern_->size());
  reset();
}

nlohmann::json CorotationalFemModel::parameters() const {
  return param_table().to_json(params_);
}

void CorotationalFemModel::reset() {
  positions_ = rest_positions_;
  velocities_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  constraint_forces_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  published_forces_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  published_vertices_.clear();
  velocity_change_ = Eigen::VectorXd::Zero(pattern_->size());
  solver_->forget();
  renumbering_.publish(positions_, velocities_);
  std::fill(quaternions_.begin(), quaternions_.end(), Eigen::Quaterniond::Identity());
  std::fill(rotations_.begin(), rotations_.end(), Eigen::Matrix3d::Identity());
  std::fill(deformations_.begin(), deformations_.end(), Eigen::Matrix3d::Identity());
  for (int t = 0; t < num_elements_; ++t) {
    // At rest (and always, for linear FEM): w_a = sqrt(V) b_a.
    Matrix34d& w = element_gradients_[static_cast<std::size_t>(t)];
    w.rightCols<3>() =
        lane_of(rest_batches_[static_cast<std::size_t>(t / kElementLanes)].scaled_gradients,
                t % kElementLanes);
    w.col(0) = -w.rightCols<3>().rowwise().sum();
  }
}

void CorotationalFemModel::set_state(const Eigen::Matrix3Xd& positions,
                                     const Eigen::Matrix3Xd& velocities) {
  check_state(positions, velocities);
  renumbering_.to_inner(positions, positions_);
  renumbering_.to_inner(velocities, velocities_);
  renumbering_.publish(positions_, velocities_);
}

void CorotationalFemModel::set_velocities(const Eigen::Matrix3Xd& velocities) {
  check_velocities(velocities);
  renumbering_.to_inner(velocities, velocities_);
  renumbering_.publish(positions_, velocities_);
  velocity_change_.setZero();
  solver_->forget();
}

TetRest CorotationalFemModel::rest_of(int t) const {
  const RestBatch& batch = rest_batches_[static_cast<std::size_t>(t / kElementLanes)];
  return {lane_of(batch.rest_inverse, t % kElementLanes), batch.volume[t % kElementLanes]};
}

double CorotationalFemModel::elastic_energy() const {
  const bool corotational =
      params_.formulation == CorotationalFemParams::Formulation::kCorotational;
  double energy = 0.0;
  for (int t = 0; t < num_elements_; ++t) {
    const TetRest rest = rest_of(t);
    const Eigen::Matrix3d deformation =
        deformation_gradient(rest, tet_positions(positions_, tets_, t));
    const Eigen::Matrix3d rotation =
        corotational ? rotation_by_svd(deformation) : Eigen::Matrix3d::Identity();
    energy += element_energy(rest, rotation, deformation, lame_);
  }
  return energy;
}

std::size_t CorotationalFemModel::memory_bytes() const {
  return bytes_of(tets_) + bytes_of(masses_) + bytes_of(rest_positions_)
         + bytes_of_elements(rest_batches_) + bytes_of_elements(vertex_offsets_)
         + bytes_of_elements(vertex_incidences_) + bytes_of_elements(edge_offsets_)
         + bytes_of_elements(edge_incidences_) + renumbering_.memory_bytes() + bytes_of(positions_)
         + bytes_of(velocities_) + bytes_of(constraint_forces_) + bytes_of(published_forces_)
         + bytes_of_elements(published_vertices_) + bytes_of_elements(quaternions_)
         + bytes_of_elements(deformations_) + bytes_of_elements(rotations_)
         + bytes_of_elements(element_rhs_) + bytes_of_elements(element_gradients_)
         + constraints_.memory_bytes() + pattern_->memory_bytes() + solver_->memory_bytes()
         + elimination_.memory_bytes() + bytes_of(known_changes_) + bytes_of(rhs_)
         + bytes_of(velocity_change_);
}

Eigen::Matrix3Xd CorotationalFemModel::elastic_forces() {
  compute_element_terms({.velocity_weight = 0.0, .force_scale = 1.0});
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  for (int v = 0; v < num_vertices_; ++v) {
    for (int k = vertex_offsets_[static_cast<std::size_t>(v)];
         k < vertex_offsets_[static_cast<std::size_t>(v) + 1]; ++k) {
      const int incidence = vertex_incidences_[static_cast<std::size_t>(k)];
      forces.col(v) += element_rhs_[static_cast<std::size_t>(incidence / 4)].col(incidence % 4);
    }
  }
  return renumbering_.to_outer(forces);
}

Eigen::SparseMatrix<double> CorotationalFemModel::stiffness_matrix() {
  compute_element_terms({.velocity_weight = 0.0, .force_scale = 1.0});
  const StepInput unconstrained;
  constraints_.bind(unconstrained.constraints);
  assemble(/*mass_coefficient=*/0.0, /*stiffness_coefficient=*/1.0, /*dt=*/0.0, unconstrained);
  constraints_.unbind();
  return renumbering_.to_outer(pattern_->matrix());
}

}  // namespace corotational_fem

std::unique_ptr<SoftBody> make_corotational_fem(const TetMesh& mesh,
                                                const Material& material,
                                                const CorotationalFemParams& params) {
  validate_material(material, "make_corotational_fem: material");
  corotational_fem::validate(params, "make_corotational_fem: CorotationalFemParams");
  return std::make_unique<corotational_fem::CorotationalFemModel>(mesh, material, params);
}

}  // namespace softbench
