// SPDX-License-Identifier: MIT
// The shape-matching model: construction (clusters and the matcher's rest-shape data), state and
// the step. The per-cluster kernel is in cluster_matching.cpp, the parameter table in
// shape_matching_params.cpp.
#include "models/shape_matching/shape_matching.h"

#include "geometry/mesh_measures.h"
#include "models/finite_state.h"
#include "models/memory_bytes.h"
#include "models/shape_matching/shape_matching_model.h"
#include "models/team_loop.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softbench {
namespace shape_matching {
namespace {

Clusters clusters_for(const TetMesh& mesh, const ShapeMatchingParams& params) {
  return build_clusters(mesh.rest_positions(),
                        {params.clusters, params.cluster_radius, params.particles_per_cluster});
}

}  // namespace

ShapeMatchingModel::ShapeMatchingModel(const TetMesh& mesh,
                                       const Material& material,
                                       const ShapeMatchingParams& params)
    : params_(params),
      num_vertices_(mesh.num_vertices()),
      masses_(lumped_masses(mesh, material.density)),
      rest_positions_(mesh.rest_positions()),
      clusters_(clusters_for(mesh, params)),
      matcher_(rest_positions_, masses_, clusters_, params),
      positions_(rest_positions_),
      velocities_(Eigen::Matrix3Xd::Zero(3, num_vertices_)),
      constraint_forces_(Eigen::Matrix3Xd::Zero(3, num_vertices_)),
      predicted_(rest_positions_),
      flight_(3, num_vertices_),
      towards_(3, num_vertices_),
      squared_residuals_(Eigen::VectorXd::Zero(num_vertices_)),
      cluster_iterations_(static_cast<std::size_t>(clusters_.count()), 0),
      constraints_(num_vertices_) {
  inverse_masses_ = masses_.cwiseInverse();
  const double diagonal = bounding_box_diagonal(rest_positions_);
  diagonal_ = diagonal > 0.0 ? diagonal : 1.0;
  kinematic_.reserve(static_cast<std::size_t>(num_vertices_));
}

nlohmann::json ShapeMatchingModel::parameters() const {
  return param_table().to_json(params_);
}

void ShapeMatchingModel::reset() {
  positions_ = rest_positions_;
  predicted_ = rest_positions_;
  velocities_.setZero();
  constraint_forces_.setZero();
  matcher_.reset();
}

void ShapeMatchingModel::set_state(const Eigen::Matrix3Xd& positions,
                                   const Eigen::Matrix3Xd& velocities) {
  check_state(positions, velocities);
  positions_ = positions;
  velocities_ = velocities;
}

void ShapeMatchingModel::set_velocities(const Eigen::Matrix3Xd& velocities) {
  check_velocities(velocities);
  velocities_ = velocities;
}

double ShapeMatchingModel::elastic_energy() const {
  return std::numeric_limits<double>::quiet_NaN();
}

std::size_t ShapeMatchingModel::memory_bytes() const {
  return bytes_of(masses_) + bytes_of(rest_positions_) + bytes_of(positions_)
         + bytes_of(velocities_) + bytes_of(constraint_forces_) + bytes_of(predicted_)
         + bytes_of(flight_) + bytes_of(towards_) + bytes_of(inverse_masses_)
         + bytes_of(squared_residuals_)
         + (clusters_.seeds.size() + clusters_.offsets.size() + clusters_.members.size()
            + cluster_iterations_.size() + kinematic_.capacity())
               * sizeof(int)
         + constraints_.memory_bytes() + matcher_.memory_bytes();
}

void ShapeMatchingModel::predict(int first, int last, double dt, const StepInput& input) {
  const int count = last - first;
  // Every particle's free flight at once (vectorised over the block): v* = v + dt (g + f / m).
  auto flight = flight_.middleCols(first, count);
  flight = velocities_.middleCols(first, count);
  flight.colwise() += dt * input.gravity;
  if (input.external_forces != nullptr) {
    flight += (input.external_forces->middleCols(first, count).array().rowwise()
               * (dt * inverse_masses_.segment(first, count).transpose().array()))
                  .matrix();
  }
  predicted_.middleCols(first, count) = positions_.middleCols(first, count) + dt * flight;
  constraint_forces_.middleCols(first, count).setZero();
  // The constrained particles instead, from their state before the step.
  for (int vertex = first; vertex < last; ++vertex) {
    if (const PositionConstraint* constraint = constraints_.of(vertex)) {
      predict_constrained(vertex, *constraint, dt, input);
    }
  }
  // positions_ is the iterate from here on: the pulls move it from x*.
  velocities_.middleCols(first, count) = flight;
  positions_.middleCols(first, count) = predicted_.middleCols(first, count);
}

void ShapeMatchingModel::predict_constrained(int vertex,
                                             const PositionConstraint& constraint,
                                             double dt,
                                             const StepInput& input) {
  const double mass = masses_(vertex);
  Eigen::Vector3d force = mass * input.gravity;
  if (input.external_forces != nullptr) {
    force += input.external_forces->col(vertex);
  }
  const Eigen::Vector3d x = positions_.col(vertex);
  const Eigen::Vector3d v = velocities_.col(vertex);
  if (is_exact(&constraint)) {
    // On the target (a sliding particle: where its free flight meets the plane) before the
    // matching, so that the fit sees it there: a fully held particle anchors its clusters (the
    // matcher holds it), a sliding one drags them by its share of their mass. The reaction
    // starts as the momentum change the other forces did not make.
    const Eigen::Vector3d placed = constraint.place(x + dt * (v + (dt / mass) * force));
    const Eigen::Vector3d velocity = (placed - x) / dt;
    constraint_forces_.col(vertex) = mass * (velocity - v) / dt - force;
    flight_.col(vertex) = velocity;
    predicted_.col(vertex) = placed;
  } else if (is_penalty(&constraint)) {
    // The spring k (target - x) by backward Euler on this particle alone, stable at any dt:
    // (m + dt^2 k) v* = m v + dt (f + k (target - x)).
    const double k = constraint.stiffness;
    flight_.col(vertex) = (mass * v + dt * (force + k * constraint.gap(x))) / (mass + dt * dt * k);
    predicted_.col(vertex) = x + dt * flight_.col(vertex);
  }
}

void ShapeMatchingModel::pull(int first, int last, double dt) {
  const int count = last - first;
  auto towards = towards_.middleCols(first, count);
  for (int vertex = first; vertex < last; ++vertex) {
    towards.col(vertex - first) = matcher_.goal(vertex) - positions_.col(vertex);
  }
  for (int vertex = first; vertex < last; ++vertex) {
    if (const PositionConstraint* constraint = constraints_.of(vertex);
        constraint != nullptr && is_exact(constraint)) {
      pull_held(vertex, *constraint, dt);
    }
  }
  // The alpha pulls of the block at once (vectorised).
  squared_residuals_.segment(first, count) = towards.colwise().squaredNorm().transpose();
  velocities_.middleCols(first, count) += (params_.alpha / dt) * towards;
  positions_.middleCols(first, count) += params_.alpha * towards;
}

void ShapeMatchingModel::pull_held(int vertex, const PositionConstraint& constraint, double dt) {
  // Held on its target, it is denied the pull toward its goal that its clusters' fit gave it
  // (a sliding particle only the pull's normal part: it follows the rest in its plane); holding
  // it takes the opposite of the denied pull's force, m alpha H (p - g) / dt^2. A kinematic
  // particle's goals are on it (to round-off, when its held set can follow it), and it also
  // supplies what the pulls toward those anchored goals give its clusters' members.
  const Eigen::Vector3d towards_goal = towards_.col(vertex);
  const Eigen::Matrix3d& held = constraint.held;
  towards_.col(vertex) = towards_goal - held * towards_goal;  // the pull it keeps
  Eigen::Vector3d denied = held * towards_goal;
  if (matcher_.is_held(vertex)) {
    denied -= matcher_.held_pull(vertex);
  }
  constraint_forces_.col(vertex) -= masses_(vertex) * params_.alpha * denied / (dt * dt);
}

void ShapeMatchingModel::finish(int first, int last) {
  // A free particle's force stays the 0 of predict(), an exactly held one's is what predict()
  // and the pulls summed; a penalty constraint's is its spring's at the end.
  for (int vertex = first; vertex < last; ++vertex) {
    if (const PositionConstraint* constraint = constraints_.of(vertex);
        constraint != nullptr && is_penalty(constraint)) {
      constraint_forces_.col(vertex) =
          constraint->stiffness * constraint->gap(positions_.col(vertex));
    }
  }
}

StepStats ShapeMatchingModel::step(double dt, const StepInput& input) {
  constraints_.bind(input.constraints);
  // Kinematic in the fits: the particles held fully. A sliding hold (a frictionless contact, a
  // support, a symmetry plane) holds one or two directions only; as an infinite mass in the
  // fit it would pin its clusters in the free directions too (friction, or glue, by another
  // name), and an infinite mass along the held directions alone would couple the fit's three
  // coordinates into one constrained system per cluster and make the rotation fit a
  // constrained one. So a sliding particle is placed on its plane (line) before the match and
  // takes part with its own mass, as position-based engines treat contacts: the hold denies
  // it the normal part of its pull (its force), and its clusters follow it by its share.
  kinematic_.clear();
  for (const int vertex : constraints_.exact_vertices()) {
    const PositionConstraint* constraint = constraints_.of(vertex);
    if (!constraint->slides() && constraint->anchors) {
      kinematic_.push_back(vertex);  // within the reserved capacity
    }
  }
  // Only the clusters whose held set changed since the last step are refitted.
  const int refits = matcher_.hold_changes(kinematic_);
  const int num_clusters = matcher_.num_clusters();
  const bool parallel = matcher_.worth_parallel();
  constexpr int kChunk = ClusterMatcher::kParticleChunk;
  // Dynamic schedules: cluster sizes differ (73 to 142 particles on the liver), and on a shared
  // machine a thread held up by another process does not hold back a fixed share. Each cluster
  // and particle is computed the same whichever thread takes it, and the per-particle gathers
  // run in a fixed order: the results are bit-identical on any number of threads.
  maybe_parallel(parallel, [&] {
    team_blocks(parallel, num_vertices_, kChunk,
                [&](int first, int last) { predict(first, last, dt, input); });
    team_loop(parallel, refits, [&](int c) { matcher_.refit_held(c); });
    for (int pass = 0; pass < params_.iterations; ++pass) {
      team_loop(parallel, num_clusters, [&](int k) {
        const auto slot = static_cast<std::size_t>(k);
        const int taken = matcher_.match_cluster(k, positions_);
        cluster_iterations_[slot] = pass == 0 ? taken : std::max(cluster_iterations_[slot], taken);
      });
      team_blocks(parallel, num_vertices_, kChunk,
                  [&](int first, int last) { pull(first, last, dt); });
    }
    team_blocks(parallel, num_vertices_, kChunk, [&](int first, int last) { finish(first, last); });
  });

  // Serial reductions in a fixed order: the same stats on any number of threads.
  StepStats stats;
  stats.iterations = *std::max_element(cluster_iterations_.begin(), cluster_iterations_.end());
  int free_particles = num_vertices_;
  for (const int vertex : constraints_.vertices()) {
    const PositionConstraint* constraint = constraints_.of(vertex);
    if (is_penalty(constraint)) {
      stats.max_constraint_error =
          std::max(stats.max_constraint_error, constraint->gap(positions_.col(vertex)).norm());
    } else {
      --free_particles;  // exactly on its target
    }
  }
  stats.residual =
      free_particles > 0 ? std::sqrt(squared_residuals_.sum() / free_particles) / diagonal_ : 0.0;
  stats.finite = state_finite(positions_, velocities_);
  constraints_.unbind();
  return stats;
}

}  // namespace shape_matching

std::unique_ptr<SoftBody> make_shape_matching(const TetMesh& mesh,
                                              const Material& material,
                                              const ShapeMatchingParams& params) {
  validate_material(material, "make_shape_matching: material");
  shape_matching::validate(params, "make_shape_matching: ShapeMatchingParams");
  return std::make_unique<shape_matching::ShapeMatchingModel>(mesh, material, params);
}

}  // namespace softbench
