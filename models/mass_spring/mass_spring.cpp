// SPDX-License-Identifier: MIT
// The mass-spring model: construction (all precomputation) and state. The step is in
// mass_spring_step.cpp, the parameter table in mass_spring_params.cpp.
#include "models/mass_spring/mass_spring.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "models/mass_spring/mass_spring_model.h"
#include "models/memory_bytes.h"

#include <array>
#include <utility>

namespace softbench {
namespace mass_spring {
namespace {

/// The spring joining vertices a and b, found among a's incident springs.
int spring_between(int a, int b, const Eigen::Matrix2Xi& springs, const SpringSystem& system) {
  for (int k = system.incident_begin(a); k < system.incident_end(a); ++k) {
    const int spring = system.incident_springs()[static_cast<std::size_t>(k)];
    if (springs(0, spring) + springs(1, spring) - a == b) {
      return spring;
    }
  }
  return -1;  // unreachable: every tet edge is a spring
}

/// Van Gelder (1998): k_e = E * (sum of the volumes of the tets sharing e) / L_e^2, the spring
/// stiffness whose stored energy under a uniform strain approximates the continuum's.
Eigen::VectorXd volume_weighted_stiffness(const TetMesh& mesh,
                                          double young_modulus,
                                          const Eigen::Matrix2Xi& springs,
                                          const Eigen::VectorXd& rest_lengths,
                                          const SpringSystem& system) {
  constexpr std::array<std::pair<int, int>, 6> kTetEdges{
      {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
  Eigen::VectorXd volume_around = Eigen::VectorXd::Zero(springs.cols());
  const Eigen::Matrix3Xd& x = mesh.rest_positions();
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::Vector4i tet = mesh.tets().col(t);
    const double volume =
        signed_tet_volume(x.col(tet(0)), x.col(tet(1)), x.col(tet(2)), x.col(tet(3)));
    for (const auto& [a, b] : kTetEdges) {
      volume_around(spring_between(tet(a), tet(b), springs, system)) += volume;
    }
  }
  return young_modulus * volume_around.cwiseQuotient(rest_lengths.cwiseAbs2());
}

}  // namespace

MassSpringModel::MassSpringModel(const TetMesh& mesh,
                                 const Material& material,
                                 const MassSpringParams& params)
    : params_(params),
      num_vertices_(mesh.num_vertices()),
      springs_(unique_edges(mesh.tets())),  // sorted, as SpringSystem needs them
      masses_(lumped_masses(mesh, material.density)),
      rest_positions_(mesh.rest_positions()),
      total_mass_(masses_.sum()),
      rest_size_(bounding_box_diagonal(rest_positions_)),
      system_(mesh.num_vertices(), springs_),
      constraints_(mesh.num_vertices()) {
  const Eigen::Index num_springs = springs_.cols();
  rest_lengths_.resize(num_springs);
  for (Eigen::Index e = 0; e < num_springs; ++e) {
    rest_lengths_(e) =
        (rest_positions_.col(springs_(1, e)) - rest_positions_.col(springs_(0, e))).norm();
  }

  if (params_.stiffness_from == MassSpringParams::StiffnessFrom::kYoungModulus) {
    spring_stiffness_ =
        volume_weighted_stiffness(mesh, material.young_modulus, springs_, rest_lengths_, system_);
  } else {
    spring_stiffness_ = Eigen::VectorXd::Constant(num_springs, params_.stiffness);
  }
  spring_stiffness_ *= params_.stiffness_scale;
  spring_damping_ =
      (params_.damping + params_.rayleigh_stiffness * spring_stiffness_.array()).matrix();

  spring_forces_.resize(3, num_springs);
  if (params_.integrator == MassSpringParams::Integrator::kImplicitEuler) {
    const Eigen::Index size = 3 * static_cast<Eigen::Index>(num_vertices_);
    spring_rhs_.resize(3, num_springs);
    known_changes_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
    rhs_.resize(size);
    if (params_.solver == MassSpringParams::LinearSolver::kCholmod) {
      pattern_ = std::make_unique<BlockPattern>(num_vertices_, springs_);
      LinearSolverOptions options;
      options.kind = LinearSolverOptions::Kind::kCholmod;
      solver_ = make_system_solver(options, *pattern_);
      cholmod_rhs_.resize(size);
    }
  }
  reset();
}

nlohmann::json MassSpringModel::parameters() const {
  return param_table().to_json(params_);
}

void MassSpringModel::reset() {
  positions_ = rest_positions_;
  velocities_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  constraint_forces_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  if (params_.integrator == MassSpringParams::Integrator::kImplicitEuler) {
    velocity_change_ = Eigen::VectorXd::Zero(3 * static_cast<Eigen::Index>(num_vertices_));
    drop_warm_start();
  }
}

void MassSpringModel::drop_warm_start() {
  system_.forget_solutions();
}

void MassSpringModel::set_state(const Eigen::Matrix3Xd& positions,
                                const Eigen::Matrix3Xd& velocities) {
  check_state(positions, velocities);
  positions_ = positions;
  velocities_ = velocities;
  // The warm start's past solutions stay: a step repeated from its start (the instrument
  // contact's passes) finds the last pass's solution among them.
}

void MassSpringModel::set_velocities(const Eigen::Matrix3Xd& velocities) {
  check_velocities(velocities);
  velocities_ = velocities;
  drop_warm_start();
}

double MassSpringModel::elastic_energy() const {
  double energy = 0.0;
  for (Eigen::Index e = 0; e < springs_.cols(); ++e) {
    const double length = (positions_.col(springs_(1, e)) - positions_.col(springs_(0, e))).norm();
    const double stretch = length - rest_lengths_(e);
    energy += 0.5 * spring_stiffness_(e) * stretch * stretch;
  }
  return energy;
}

std::size_t MassSpringModel::memory_bytes() const {
  std::size_t bytes = bytes_of(springs_) + bytes_of(rest_lengths_) + bytes_of(spring_stiffness_)
                      + bytes_of(spring_damping_) + bytes_of(masses_) + bytes_of(rest_positions_)
                      + bytes_of(positions_) + bytes_of(velocities_) + bytes_of(constraint_forces_)
                      + bytes_of(spring_forces_) + bytes_of(spring_rhs_) + bytes_of(known_changes_)
                      + bytes_of(rhs_) + bytes_of(velocity_change_) + system_.memory_bytes()
                      + constraints_.memory_bytes();
  if (pattern_ != nullptr) {
    bytes += pattern_->memory_bytes() + solver_->memory_bytes() + elimination_.memory_bytes()
             + bytes_of(cholmod_rhs_);
  }
  return bytes;
}

}  // namespace mass_spring

std::unique_ptr<SoftBody> make_mass_spring(const TetMesh& mesh,
                                           const Material& material,
                                           const MassSpringParams& params) {
  validate_material(material, "make_mass_spring: material");
  mass_spring::validate(params, "make_mass_spring: MassSpringParams");
  return std::make_unique<mass_spring::MassSpringModel>(mesh, material, params);
}

}  // namespace softbench
