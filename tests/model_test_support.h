// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"
#include "geometry/mesh_validation.h"
#include "geometry/tet_mesh.h"
#include "models/soft_body.h"
#include "tests/test_meshes.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <random>
#include <span>
#include <vector>

// Constraint and input helpers every model's tests use: write each once.
namespace softbench::test {

/// Holds every vertex at `targets`.
inline std::vector<PositionConstraint> pin_all(const Eigen::Matrix3Xd& targets) {
  std::vector<PositionConstraint> pins;
  for (int v = 0; v < targets.cols(); ++v) {
    pins.push_back({v, targets.col(v), kExact});
  }
  return pins;
}

/// Exact pins on every vertex with x <= min x (+ a hair): one face of a box.
inline std::vector<PositionConstraint> pin_min_x_face(const TetMesh& mesh) {
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const double min_x = rest.row(0).minCoeff();
  std::vector<PositionConstraint> pins;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (rest(0, v) <= min_x + 1e-12) {
      pins.push_back({v, rest.col(v), kExact});
    }
  }
  return pins;
}

inline StepInput no_gravity(std::span<const PositionConstraint> constraints = {}) {
  StepInput input;
  input.gravity.setZero();
  input.constraints = constraints;
  return input;
}

/// Puts the body at `targets` with zero velocity: the first exact step lands it there, the
/// second holds it, leaving v = (target - target) / dt = 0 exactly.
inline void place_at_rest(SoftBody& body, const Eigen::Matrix3Xd& targets) {
  const std::vector<PositionConstraint> pins = pin_all(targets);
  constexpr double kDt = 0.01;
  body.step(kDt, no_gravity(pins));
  body.step(kDt, no_gravity(pins));
}

/// Kinetic energy of the body's velocities with lumped `masses` (#V), J.
inline double kinetic_energy(const SoftBody& body, const Eigen::VectorXd& masses) {
  return 0.5
         * (body.velocities().colwise().squaredNorm().transpose().array() * masses.array()).sum();
}

/// Steps the body under `input` (gravity, with `pins` among its constraints) at 30 Hz until it
/// is at rest (kinetic energy below 1e-20 J, velocities ~1e-10 m/s), then expects the reactions
/// to balance its weight to 1e-6 relative and to act at the pinned vertices only.
inline void expect_reactions_balance_weight_at_rest(SoftBody& body,
                                                    const Eigen::VectorXd& masses,
                                                    const StepInput& input,
                                                    std::span<const PositionConstraint> pins) {
  constexpr double kRestKineticEnergy = 1e-20;
  int step = 0;
  for (; step < 5000 && (step < 10 || kinetic_energy(body, masses) > kRestKineticEnergy); ++step) {
    ASSERT_TRUE(body.step(1.0 / 30.0, input).finite);
  }
  ASSERT_LE(kinetic_energy(body, masses), kRestKineticEnergy) << "not at rest after " << step;

  const Eigen::Vector3d weight = masses.sum() * input.gravity;
  const Eigen::Vector3d total_reaction = body.constraint_forces().rowwise().sum();
  constexpr double kBalance = 1e-6;  // the requirement: 1e-6 relative to the weight
  EXPECT_LT((total_reaction + weight).norm(), kBalance * weight.norm())
      << "reaction " << total_reaction.transpose() << ", weight " << weight.transpose();
  Eigen::Matrix3Xd unpinned = body.constraint_forces();
  for (const PositionConstraint& pin : pins) {
    unpinned.col(pin.vertex).setZero();
  }
  EXPECT_TRUE(unpinned.isZero(0.0));  // reactions act only at the pinned vertices
}

/// Checks that the body's elastic forces at `x` are minus the gradient of its elastic energy,
/// through the interface alone: held exactly at x from rest, the constraints carry the elastic
/// force (no inertia, no damping, no gravity), so constraint_forces() = dE/dx; each component is
/// compared with a central difference of elastic_energy() over positions held the same way.
/// The largest mismatch must be below `tolerance` times the largest force (the difference step is
/// 1e-6 of the body's size: truncation and round-off stay below 1e-8 relative).
inline void expect_forces_match_energy_gradient(SoftBody& body,
                                                const Eigen::Matrix3Xd& x,
                                                double tolerance) {
  const std::vector<PositionConstraint> pins = pin_all(x);
  place_at_rest(body, x);
  ASSERT_TRUE(body.step(0.01, no_gravity(pins)).finite);
  const Eigen::Matrix3Xd gradient = body.constraint_forces();
  const double largest = gradient.cwiseAbs().maxCoeff();
  ASSERT_GT(largest, 0.0) << "no elastic force at a deformed state";
  const double size = (x.rowwise().maxCoeff() - x.rowwise().minCoeff()).norm();
  const double h = 1e-6 * size;
  const auto energy_at = [&](const Eigen::Matrix3Xd& y) {
    place_at_rest(body, y);
    return body.elastic_energy();
  };
  double worst = 0.0;
  for (Eigen::Index v = 0; v < x.cols(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Matrix3Xd plus = x;
      Eigen::Matrix3Xd minus = x;
      plus(axis, v) += h;
      minus(axis, v) -= h;
      const double difference = (energy_at(plus) - energy_at(minus)) / (2.0 * h);
      worst = std::max(worst, std::abs(difference - gradient(axis, v)));
    }
  }
  EXPECT_LT(worst, tolerance * largest)
      << "largest force " << largest << " N, largest mismatch " << worst << " N";
}

/// For a model that numbers the vertices its own way (what goes in and out is in the mesh's
/// numbering): the same box numbered at random, driven the same way (pins, a penalty grasp, a
/// force, a new velocity field, a new state), moves the same to round-off. `make` builds the
/// model with exact solves (any difference then is the numbering's).
template <class MakeBody>
void expect_motion_independent_of_vertex_numbering(const MakeBody& make) {
  constexpr double kDt = 1.0 / 60.0;
  constexpr double kAgreement = 1e-9;  // relative: round-off of differently ordered sums
  const MeshData box = box_tets(5, 2, 2, 0.25, 0.1, 0.1);
  const auto num_vertices = static_cast<int>(box.vertices.cols());
  std::vector<int> new_of_old(static_cast<std::size_t>(num_vertices));
  std::iota(new_of_old.begin(), new_of_old.end(), 0);
  std::mt19937 random(11);
  std::shuffle(new_of_old.begin(), new_of_old.end(), random);
  const auto renumber = [&](const Eigen::Matrix3Xd& in) {
    Eigen::Matrix3Xd out(3, in.cols());
    for (int v = 0; v < num_vertices; ++v) {
      out.col(new_of_old[static_cast<std::size_t>(v)]) = in.col(v);
    }
    return out;
  };
  MeshData shuffled = box;
  shuffled.vertices = renumber(box.vertices);
  for (Eigen::Index t = 0; t < box.tetrahedra.cols(); ++t) {
    for (int a = 0; a < 4; ++a) {
      shuffled.tetrahedra(a, box.tetrahedra.cols() - 1 - t) =
          new_of_old[static_cast<std::size_t>(box.tetrahedra(a, t))];
    }
  }
  const TetMesh meshes[] = {make_tet_mesh(box), make_tet_mesh(shuffled)};

  const int grasped = 3 * num_vertices / 4;
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, num_vertices);
  forces.col(num_vertices / 2) = Eigen::Vector3d(0.0, 0.3, -0.5);  // N
  Eigen::Matrix3Xd spin(3, num_vertices);  // 2 rad/s about z through the centroid
  const Eigen::Vector3d centroid = box.vertices.rowwise().mean();
  for (int v = 0; v < num_vertices; ++v) {
    spin.col(v) = Eigen::Vector3d(0.0, 0.0, 2.0).cross(box.vertices.col(v) - centroid);
  }
  std::vector<std::unique_ptr<SoftBody>> bodies;
  for (int k = 0; k < 2; ++k) {
    const TetMesh& mesh = meshes[k];
    const auto vertex = [&](int v) { return k == 0 ? v : new_of_old[static_cast<std::size_t>(v)]; };
    std::vector<PositionConstraint> constraints = pin_min_x_face(mesh);
    constraints.push_back({vertex(grasped),
                           mesh.rest_positions().col(vertex(grasped)) + Eigen::Vector3d(0, 0, 0.01),
                           500.0});
    const Eigen::Matrix3Xd body_forces = k == 0 ? forces : renumber(forces);
    StepInput input;
    input.constraints = constraints;
    input.external_forces = &body_forces;
    std::unique_ptr<SoftBody> body = make(mesh);
    for (int step = 0; step < 10; ++step) {
      ASSERT_TRUE(body->step(kDt, input).finite);
    }
    body->set_velocities(k == 0 ? spin : renumber(spin));
    for (int step = 0; step < 5; ++step) {
      ASSERT_TRUE(body->step(kDt, input).finite);
    }
    // A new state: the rest shape, lifted, at rest.
    const Eigen::Matrix3Xd lifted = mesh.rest_positions().colwise() + Eigen::Vector3d(0, 0, 0.02);
    body->set_state(lifted, Eigen::Matrix3Xd::Zero(3, num_vertices));
    ASSERT_TRUE(body->step(kDt, input).finite);
    bodies.push_back(std::move(body));
  }
  const double scale = (bodies[0]->positions() - meshes[0].rest_positions()).cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 1e-3);
  EXPECT_LT((renumber(bodies[0]->positions()) - bodies[1]->positions()).cwiseAbs().maxCoeff(),
            kAgreement * scale);
  EXPECT_TRUE(renumber(bodies[0]->velocities()).isApprox(bodies[1]->velocities(), kAgreement));
  EXPECT_TRUE(renumber(bodies[0]->constraint_forces())
                  .isApprox(bodies[1]->constraint_forces(), kAgreement));
  EXPECT_NEAR(bodies[0]->elastic_energy(), bodies[1]->elastic_energy(),
              kAgreement * bodies[0]->elastic_energy());
}

}  // namespace softbench::test
