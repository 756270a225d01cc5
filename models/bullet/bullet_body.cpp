// SPDX-License-Identifier: MIT
// The adapter core shared by both Bullet models: loading the mesh into a btSoftBody, mapping
// constraints onto kinematic nodes and forces, copying the state back, reactions.
#include "models/bullet/bullet_body.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "models/bullet/bullet_vectors.h"

#include <BulletSoftBody/btSoftBody.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace softbench::bullet {

BulletMesh BulletMesh::from(const TetMesh& mesh, double density) {
  return {mesh.rest_positions(), mesh.tets(), unique_edges(mesh.tets()),
          lumped_masses(mesh, density)};
}

std::unique_ptr<btSoftBody> make_soft_body(btSoftBodyWorldInfo& info,
                                           const BulletMesh& mesh,
                                           double link_stiffness) {
  const auto num_nodes = static_cast<int>(mesh.rest_positions.cols());
  btAlignedObjectArray<btVector3> x;
  btAlignedObjectArray<btScalar> m;
  x.resize(num_nodes);
  m.resize(num_nodes);
  for (int i = 0; i < num_nodes; ++i) {
    x[i] = to_bullet(mesh.rest_positions.col(i));
    m[i] = mesh.masses(i);
  }
  auto body = std::make_unique<btSoftBody>(&info, num_nodes, &x[0], &m[0]);
  body->m_materials[0]->m_kLST = link_stiffness;
  // The edges are unique already: Bullet's own duplicate check is linear per link.
  for (Eigen::Index e = 0; e < mesh.edges.cols(); ++e) {
    body->appendLink(mesh.edges(0, e), mesh.edges(1, e), nullptr, /*bcheckexist=*/false);
  }
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    body->appendTetra(mesh.tets(0, t), mesh.tets(1, t), mesh.tets(2, t), mesh.tets(3, t));
  }
  body->m_cfg.collisions = 0;  // contacts arrive as PositionConstraints, not from Bullet
  body->m_sleepingThreshold = 0;
  body->setActivationState(DISABLE_DEACTIVATION);
  return body;
}

BulletBody::BulletBody(std::string name,
                       nlohmann::json parameters,
                       BulletMesh mesh,
                       WorldFactory make_world)
    : name_(std::move(name)),
      parameters_(std::move(parameters)),
      mesh_(std::move(mesh)),
      make_world_(std::move(make_world)) {
  reset();
}

BulletBody::~BulletBody() = default;

void BulletBody::reset() {
  forces_estimated_ = false;
  // A fresh world: Bullet keeps state in many places (pose frames, clusters, solver scratch,
  // dbvt trees), so rebuilding is the only exact restore.
  world_.reset();
  world_ = make_world_(mesh_);
  const auto num_nodes = mesh_.rest_positions.cols();
  positions_ = mesh_.rest_positions;
  velocities_ = Eigen::Matrix3Xd::Zero(3, num_nodes);
  kinematic_.assign(static_cast<std::size_t>(num_nodes), 0);
  diverged_ = false;
  last_ = LastStep{};
}

void BulletBody::update_kinematic_nodes(const std::vector<int>& exact) {
  btSoftBody& body = world_->body();
  kinematic_next_.assign(kinematic_.size(), 0);
  for (int node : exact) {
    kinematic_next_[static_cast<std::size_t>(node)] = 1;
  }
  for (std::size_t i = 0; i < kinematic_.size(); ++i) {
    if (kinematic_next_[i] != kinematic_[i]) {
      const auto node = static_cast<int>(i);
      body.setMass(node, kinematic_next_[i] != 0 ? 0.0 : mesh_.masses(node));
    }
  }
  kinematic_.swap(kinematic_next_);
}

StepStats BulletBody::step(double dt, const StepInput& input) {
  forces_estimated_ = false;
  StepStats stats;
  if (diverged_) {
    stats.finite = false;  // Bullet is not called on a NaN state: it may loop or crash there
    return stats;
  }
  exact_.clear();
  exact_targets_.clear();
  penalties_.clear();
  const auto num_vertices = static_cast<int>(positions_.cols());
  for (const PositionConstraint& constraint : input.constraints) {
    if (constraint.vertex < 0 || constraint.vertex >= num_vertices) {
      continue;  // as VertexConstraints: out of range is ignored, step() never throws
    }
    // Bullet has no sliding constraint: a sliding one holds its vertex where the free flight
    // x + dt v meets the plane, so the vertex slides from step to step but not within one.
    const Eigen::Vector3d target = constraint.slides()
                                       ? constraint.place(positions_.col(constraint.vertex)
                                                          + dt * velocities_.col(constraint.vertex))
                                       : constraint.target;
    if (std::isinf(constraint.stiffness)) {
      exact_.push_back(constraint.vertex);
      exact_targets_.push_back(target);
    } else {
      penalties_.push_back({constraint.vertex, target, constraint.stiffness});
    }
  }
  update_kinematic_nodes(exact_);

  btSoftBody& body = world_->body();
  // Kinematic nodes: Bullet integrates x += dt v and no solver touches a zero-mass node, so this
  // velocity lands them on the target. m_vn too: the implicit solver restarts from it.
  exact_velocities_.clear();
  for (std::size_t k = 0; k < exact_.size(); ++k) {
    exact_velocities_.push_back((exact_targets_[k] - positions_.col(exact_[k])) / dt);
    btSoftBody::Node& node = body.m_nodes[exact_[k]];
    node.m_v = to_bullet(exact_velocities_.back());
    node.m_vn = node.m_v;
  }
  last_.taken = true;
  last_.dt = dt;
  last_.gravity = input.gravity;
  last_.velocities_before = velocities_;
  if (input.external_forces != nullptr) {
    last_.external_forces = *input.external_forces;
  } else {
    last_.external_forces.setZero(3, positions_.cols());
  }
  last_.exact = exact_;
  last_.penalties = penalties_;

  world_->set_gravity(input.gravity);
  world_->set_loads(input.external_forces, penalties_);
  const BulletWorld::Counters counters = world_->advance(dt);
  stats.iterations = counters.iterations;
  stats.linear_solves = counters.linear_solves;

  for (int i = 0; i < body.m_nodes.size(); ++i) {
    positions_.col(i) = to_eigen(body.m_nodes[i].m_x);
    velocities_.col(i) = to_eigen(body.m_nodes[i].m_v);
  }
  // Write the targets and their velocities themselves: Bullet's own integration leaves
  // round-off, and the position-based solver scales every velocity by (1 - kDP).
  for (std::size_t k = 0; k < exact_.size(); ++k) {
    const int i = exact_[k];
    const Eigen::Vector3d& target = exact_targets_[k];
    stats.residual = std::max(stats.residual, (positions_.col(i) - target).norm());
    btSoftBody::Node& node = body.m_nodes[i];
    node.m_x = to_bullet(target);
    node.m_q = node.m_x;
    node.m_v = to_bullet(exact_velocities_[k]);
    node.m_vn = node.m_v;
    positions_.col(i) = target;
    velocities_.col(i) = exact_velocities_[k];
  }
  for (const PenaltySpring& spring : penalties_) {
    stats.max_constraint_error =
        std::max(stats.max_constraint_error, (positions_.col(spring.node) - spring.target).norm());
  }
  stats.finite = positions_.allFinite() && velocities_.allFinite();
  diverged_ = !stats.finite;
  return stats;
}

void BulletBody::set_velocities(const Eigen::Matrix3Xd& velocities) {
  forces_estimated_ = false;
  check_velocities(velocities);
  if (last_.taken) {
    // The reaction estimate is m (v_after - v_before) / dt - f: shift both ends alike.
    last_.velocities_before += velocities - velocities_;
  }
  velocities_ = velocities;
  btSoftBody& body = world_->body();
  for (int i = 0; i < body.m_nodes.size(); ++i) {
    btSoftBody::Node& node = body.m_nodes[i];
    node.m_v = to_bullet(velocities_.col(i));
    node.m_vn = node.m_v;
  }
}

void BulletBody::set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) {
  check_state(positions, velocities);
  positions_ = positions;
  btSoftBody& body = world_->body();
  for (int i = 0; i < body.m_nodes.size(); ++i) {
    btSoftBody::Node& node = body.m_nodes[i];
    node.m_x = to_bullet(positions_.col(i));
    node.m_q = node.m_x;
  }
  set_velocities(velocities);
}

const Eigen::Matrix3Xd& BulletBody::constraint_forces() const {
  if (!forces_estimated_) {
    constraint_forces_ = estimate_constraint_forces();
    forces_estimated_ = true;
  }
  return constraint_forces_;
}

Eigen::Matrix3Xd BulletBody::estimate_constraint_forces() const {
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, positions_.cols());
  if (!last_.taken || diverged_) {
    return forces;
  }
  for (const PenaltySpring& spring : last_.penalties) {
    forces.col(spring.node) += spring.stiffness * (spring.target - positions_.col(spring.node));
  }
  if (last_.exact.empty()) {
    return forces;
  }
  // Newton per node: m a = m g + f_external + f_internal + f_constraint.
  const auto balance = [&](int i) -> Eigen::Vector3d {
    return mesh_.masses(i)
               * ((velocities_.col(i) - last_.velocities_before.col(i)) / last_.dt - last_.gravity)
           - last_.external_forces.col(i);
  };
  const std::optional<Eigen::Matrix3Xd> internal = world_->internal_forces();
  if (internal) {
    for (int i : last_.exact) {
      forces.col(i) = balance(i) - internal->col(i);
    }
    return forces;
  }
  // No per-node forces (position-based solver): the body's internal forces cancel in the sum, so
  // the total reaction is the momentum balance of the whole body; share it by mass.
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < positions_.cols(); ++i) {
    total += balance(static_cast<int>(i));
  }
  for (const PenaltySpring& spring : last_.penalties) {
    total -= forces.col(spring.node);
  }
  double held_mass = 0.0;
  for (int i : last_.exact) {
    held_mass += mesh_.masses(i);
  }
  for (int i : last_.exact) {
    forces.col(i) = total * (mesh_.masses(i) / held_mass);
  }
  return forces;
}

double BulletBody::elastic_energy() const {
  if (diverged_) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return world_->elastic_energy(positions_);
}

std::size_t BulletBody::memory_bytes() const {
  const auto doubles = static_cast<std::size_t>(
      mesh_.rest_positions.size() + mesh_.masses.size() + positions_.size() + velocities_.size()
      + last_.velocities_before.size() + last_.external_forces.size());
  const auto ints = static_cast<std::size_t>(mesh_.tets.size() + mesh_.edges.size());
  return world_->memory_bytes() + doubles * sizeof(double) + ints * sizeof(int) + kinematic_.size();
}

}  // namespace softbench::bullet
