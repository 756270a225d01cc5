// SPDX-License-Identifier: MIT
// The neo-Hookean reference model: construction (all precomputation), state, energy, and the
// entry points tests use. The Newton step is in neo_hookean_step.cpp, the parameters in
// neo_hookean_params.cpp.
#include "models/neo_hookean/neo_hookean.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "models/memory_bytes.h"
#include "models/neo_hookean/neo_hookean_model.h"

#include <algorithm>
#include <array>
#include <utility>

namespace softbench {
namespace neo_hookean {
NeoHookeanModel::NeoHookeanModel(const TetMesh& mesh,
                                 const Material& material,
                                 const NeoHookeanParams& params)
    : params_(params),
      law_(stable_neo_hookean(lame_parameters(material))),
      num_vertices_(mesh.num_vertices()),
      num_elements_(mesh.num_tets()),
      tets_(mesh.tets()),
      masses_(lumped_masses(mesh, material.density)),
      rest_positions_(mesh.rest_positions()),
      constraints_(mesh.num_vertices()) {
  length_scale_ = bounding_box_diagonal(rest_positions_);

  const auto num_elements = static_cast<std::size_t>(num_elements_);
  elements_.reserve(num_elements);
  for (int t = 0; t < num_elements_; ++t) {
    elements_.push_back(tet_rest(tet_positions(rest_positions_, tets_, t)));
  }

  const Eigen::Matrix2Xi edges = unique_edges(tets_);
  pattern_ = std::make_unique<BlockPattern>(num_vertices_, edges);
  element_blocks_.resize(16 * num_elements);
  for (int t = 0; t < num_elements_; ++t) {
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        const int row = tets_(a, t);
        const int column = tets_(b, t);
        BlockEntries& entries =
            element_blocks_[16 * static_cast<std::size_t>(t) + static_cast<std::size_t>(4 * a + b)];
        if (row == column) {
          entries = pattern_->vertex_block(row);
        } else if (row < column) {
          entries = pattern_->edge_block(edge_index(edges, row, column));
        } else {
          entries = pattern_->edge_block_transposed(edge_index(edges, column, row));
        }
      }
    }
  }
  LinearSolverOptions options;
  options.kind = LinearSolverOptions::Kind::kCholmod;
  solver_ = make_system_solver(options, *pattern_);

  element_energies_.resize(num_elements);
  element_gradients_.resize(num_elements);
  element_hessians_.resize(num_elements);
  previous_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  predicted_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  trial_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  gradient_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  zero_change_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  rhs_ = Eigen::VectorXd::Zero(pattern_->size());
  newton_step_ = Eigen::VectorXd::Zero(pattern_->size());
  reset();
}

nlohmann::json NeoHookeanModel::parameters() const {
  return param_table().to_json(params_);
}

void NeoHookeanModel::reset() {
  positions_ = rest_positions_;
  velocities_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  constraint_forces_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
}

void NeoHookeanModel::set_state(const Eigen::Matrix3Xd& positions,
                                const Eigen::Matrix3Xd& velocities) {
  check_state(positions, velocities);
  positions_ = positions;
  velocities_ = velocities;
}

void NeoHookeanModel::set_velocities(const Eigen::Matrix3Xd& velocities) {
  check_velocities(velocities);
  velocities_ = velocities;
}

double NeoHookeanModel::elastic_energy() const {
  double energy = 0.0;
  for (int t = 0; t < num_elements_; ++t) {
    const TetRest& rest = elements_[static_cast<std::size_t>(t)];
    energy +=
        rest.volume
        * energy_density(deformation_gradient(rest, tet_positions(positions_, tets_, t)), law_);
  }
  return energy;
}

std::size_t NeoHookeanModel::memory_bytes() const {
  return bytes_of(tets_) + bytes_of(masses_) + bytes_of(rest_positions_)
         + bytes_of_elements(elements_) + bytes_of_elements(element_blocks_) + bytes_of(positions_)
         + bytes_of(velocities_) + bytes_of(constraint_forces_)
         + bytes_of_elements(element_energies_) + bytes_of_elements(element_gradients_)
         + bytes_of_elements(element_hessians_) + constraints_.memory_bytes()
         + pattern_->memory_bytes() + solver_->memory_bytes() + elimination_.memory_bytes()
         + bytes_of(previous_) + bytes_of(predicted_) + bytes_of(trial_) + bytes_of(gradient_)
         + bytes_of(zero_change_) + bytes_of(rhs_) + bytes_of(newton_step_);
}

Eigen::Matrix3Xd NeoHookeanModel::elastic_gradient() {
  evaluate_elements(positions_, Derivatives::kGradient);
  Eigen::Matrix3Xd gradient = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  for (int t = 0; t < num_elements_; ++t) {
    for (int a = 0; a < 4; ++a) {
      gradient.col(tets_(a, t)) += element_gradients_[static_cast<std::size_t>(t)].col(a);
    }
  }
  return gradient;
}

Eigen::SparseMatrix<double> NeoHookeanModel::elastic_hessian(bool projected) {
  evaluate_elements(positions_, projected ? Derivatives::kGradientAndProjectedHessian
                                          : Derivatives::kGradientAndHessian);
  Potential elastic_only;  // no inertia: mass_coefficient 0
  assemble_hessian(elastic_only);
  return pattern_->matrix();
}

}  // namespace neo_hookean

std::unique_ptr<SoftBody> make_neo_hookean(const TetMesh& mesh,
                                           const Material& material,
                                           const NeoHookeanParams& params) {
  validate_material(material, "make_neo_hookean: material");
  neo_hookean::validate(params, "make_neo_hookean: NeoHookeanParams");
  return std::make_unique<neo_hookean::NeoHookeanModel>(mesh, material, params);
}

}  // namespace softbench
