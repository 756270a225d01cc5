// SPDX-License-Identifier: MIT
// Projective Dynamics: construction (the constant matrix and its analysis), state, energy. The
// step is in projective_dynamics_step.cpp, the parameters in projective_dynamics_params.cpp.
#include "models/projective_dynamics/projective_dynamics.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "models/corotational_fem/polar_decomposition.h"
#include "models/corotational_fem/tet_element.h"
#include "models/memory_bytes.h"
#include "models/projective_dynamics/projective_dynamics_model.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace softbench {
namespace projective_dynamics {

ProjectiveDynamicsModel::ProjectiveDynamicsModel(const TetMesh& mesh,
                                                 const Material& material,
                                                 const ProjectiveDynamicsParams& params)
    : params_(params),
      lame_(lame_parameters(material)),
      num_vertices_(mesh.num_vertices()),
      num_elements_(mesh.num_tets()),
      tets_(mesh.tets()),
      masses_(lumped_masses(mesh, material.density)),
      rest_positions_(mesh.rest_positions()),
      rest_size_(bounding_box_diagonal(rest_positions_)),
      eliminated_(static_cast<std::size_t>(num_vertices_), 0),
      wanted_(static_cast<std::size_t>(num_vertices_), 0),
      held_rows_(num_vertices_),
      constraints_(num_vertices_) {
  const auto num_elements = static_cast<std::size_t>(num_elements_);
  elements_.reserve(num_elements);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(16 * num_elements + static_cast<std::size_t>(num_vertices_));
  for (int t = 0; t < num_elements_; ++t) {
    const TetRest rest = tet_rest(tet_positions(rest_positions_, tets_, t));
    elements_.push_back(rest);
    // Both constraints' weights: A's part is (w_s + w_v) G^T G, (G^T G)_ab = b_a . b_b.
    const double weight = rest.volume * (2.0 * lame_.mu + 3.0 * lame_.lambda);
    const Matrix34d gradients = shape_gradients(rest);
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        entries.emplace_back(tets_(a, t), tets_(b, t),
                             weight * gradients.col(a).dot(gradients.col(b)));
      }
    }
  }
  for (int v = 0; v < num_vertices_; ++v) {
    entries.emplace_back(v, v, 0.0);  // every diagonal present, for the masses
  }
  laplacian_.resize(num_vertices_, num_vertices_);
  laplacian_.setFromTriplets(entries.begin(), entries.end());
  laplacian_.makeCompressed();
  system_ = laplacian_;
  // Simplicial: its triangular solves, three right-hand sides at a time every iteration, cost
  // less than supernodal ones on the liver, and the factorisation is rare; for the same
  // reason the sparsest ordering is worth its analysis.
  factor_ = std::make_unique<CholmodFactor>(system_, /*supernodal=*/false,
                                            /*sparsest_ordering=*/true);

  // Vertex incidences, in element order: the parallel gather sums in a fixed order.
  Incidences incidences = vertex_corners(tets_, num_vertices_);
  vertex_offsets_ = std::move(incidences.offsets);
  vertex_incidences_ = std::move(incidences.items);

  quaternions_.resize(num_elements);
  deformations_.resize(num_elements);
  rotations_.resize(num_elements);
  element_sums_.resize(3, num_vertices_);
  if (num_elements_ > kParallelElements) {
    element_parts_.resize(num_elements);  // the parallel local step's per-element storage
  }
  multiplier_holds_.reserve(static_cast<std::size_t>(num_vertices_));
  inertia_.resize(3, num_vertices_);
  iterate_.resize(3, num_vertices_);
  previous_.resize(3, num_vertices_);
  next_.resize(3, num_vertices_);
  rhs_.resize(num_vertices_, 3);
  solution_.resize(num_vertices_, 3);
  reset();
}

nlohmann::json ProjectiveDynamicsModel::parameters() const {
  return param_table().to_json(params_);
}

void ProjectiveDynamicsModel::reset() {
  positions_ = rest_positions_;
  velocities_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  constraint_forces_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  std::fill(quaternions_.begin(), quaternions_.end(), Eigen::Quaterniond::Identity());
}

void ProjectiveDynamicsModel::set_velocities(const Eigen::Matrix3Xd& velocities) {
  check_velocities(velocities);
  velocities_ = velocities;  // nothing else was made for the old velocities
}

void ProjectiveDynamicsModel::set_state(const Eigen::Matrix3Xd& positions,
                                        const Eigen::Matrix3Xd& velocities) {
  check_state(positions, velocities);
  positions_ = positions;
  velocities_ = velocities;
}

double ProjectiveDynamicsModel::elastic_energy() const {
  double energy = 0.0;
  for (int t = 0; t < num_elements_; ++t) {
    const TetRest& rest = elements_[static_cast<std::size_t>(t)];
    const Eigen::Matrix3d deformation =
        deformation_gradient(rest, tet_positions(positions_, tets_, t));
    energy += corotational_fem::element_energy(
        rest, corotational_fem::rotation_by_svd(deformation), deformation, lame_);
  }
  return energy;
}

std::size_t ProjectiveDynamicsModel::memory_bytes() const {
  return bytes_of(tets_) + bytes_of(masses_) + bytes_of(rest_positions_)
         + bytes_of_elements(elements_) + bytes_of_elements(vertex_offsets_)
         + bytes_of_elements(vertex_incidences_) + bytes_of_sparse(laplacian_)
         + bytes_of_sparse(system_) + factor_->memory_bytes() + bytes_of_elements(eliminated_)
         + bytes_of_elements(eliminated_list_) + bytes_of_elements(wanted_)
         + held_rows_.memory_bytes() + bytes_of(positions_) + bytes_of(velocities_)
         + bytes_of(constraint_forces_) + bytes_of_elements(quaternions_)
         + constraints_.memory_bytes() + bytes_of_elements(multiplier_holds_)
         + bytes_of_elements(deformations_) + bytes_of_elements(rotations_)
         + bytes_of_elements(element_parts_) + bytes_of(element_sums_) + bytes_of(inertia_) + bytes_of(iterate_)
         + bytes_of(previous_) + bytes_of(next_) + bytes_of(eliminated_gradients_) + bytes_of(eliminated_targets_) + bytes_of(rhs_) + bytes_of(solution_);
}

}  // namespace projective_dynamics

std::unique_ptr<SoftBody> make_projective_dynamics(const TetMesh& mesh,
                                                   const Material& material,
                                                   const ProjectiveDynamicsParams& params) {
  validate_material(material, "make_projective_dynamics: material");
  projective_dynamics::validate(params, "make_projective_dynamics: ProjectiveDynamicsParams");
  return std::make_unique<projective_dynamics::ProjectiveDynamicsModel>(mesh, material, params);
}

}  // namespace softbench
