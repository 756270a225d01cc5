// SPDX-License-Identifier: MIT
#include "models/projective_dynamics/projective_dynamics.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "models/corotational_fem/corotational_fem.h"
#include "models/neo_hookean/neo_hookean.h"
#include "tests/model_test_support.h"
#include "tests/test_meshes.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <utility>
#include <vector>

namespace softbench {
namespace {

using test::pin_min_x_face;

/// The thesis's liver material.
const Material kPdMaterial{3000.0, 0.3, 1060.0};
constexpr double kPdDt = 1.0 / 60.0;

/// A 10 x 5 x 5 cm bar, 4 x 2 x 2 cubes of 6 tets.
const TetMesh& bar() {
  static const TetMesh mesh = make_tet_mesh(test::box_tets(4, 2, 2, 0.1, 0.05, 0.05));
  return mesh;
}

/// Gravity ramped smoothly from 0 to 9.81 m/s^2 over the first 0.2 s (no step excites the
/// bar's highest modes), at the end of step `step` (backward Euler's loads).
StepInput ramped_gravity(int step, std::span<const PositionConstraint> holds) {
  StepInput input;
  input.constraints = holds;
  constexpr double kRamp = 0.2;
  const double t = (step + 1) * kPdDt;
  input.gravity.z() =
      -9.81 * (t < kRamp ? 0.5 * (1.0 - std::cos(std::numbers::pi * t / kRamp)) : 1.0);
  return input;
}

/// The bar clamped at x = 0 after `steps` steps of ramped gravity.
Eigen::Matrix3Xd clamped_bar(SoftBody& body, int steps) {
  const std::vector<PositionConstraint> clamp = pin_min_x_face(bar());
  for (int step = 0; step < steps; ++step) {
    EXPECT_TRUE(body.step(kPdDt, ramped_gravity(step, clamp)).finite);
  }
  return body.positions();
}

double rms_distance(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

TEST(ProjectiveDynamics, SettlesWhereCorotationalFemSettles) {
  // The two constraints are corotational_fem's element energy exactly, so both models' static
  // equilibria are the same minimiser, whatever each does on the way. Damped settling runs;
  // the tolerance is what 400 steps leave of the motion (the sag is ~4 mm).
  ProjectiveDynamicsParams params;
  params.rayleigh_mass = 20.0;
  params.iterations = 20;
  auto pd = make_projective_dynamics(bar(), kPdMaterial, params);
  CorotationalFemParams fem_params;
  fem_params.solver = CorotationalFemParams::LinearSolver::kCholmod;
  fem_params.rayleigh_mass = 20.0;
  auto fem = make_corotational_fem(bar(), kPdMaterial, fem_params);
  const Eigen::Matrix3Xd pd_rest = clamped_bar(*pd, 400);
  const Eigen::Matrix3Xd fem_rest = clamped_bar(*fem, 400);
  const double sag = rms_distance(fem_rest, bar().rest_positions());
  const double difference = rms_distance(pd_rest, fem_rest);
  std::cout << "[ settle ] sag " << sag << " m, PD - FEM " << difference << " m\n";
  EXPECT_GT(sag, 1e-3);
  EXPECT_LT(difference, 1e-4 * sag);
}

TEST(ProjectiveDynamics, ErrorAgainstTheNeoHookeanReferenceFallsWithIterations) {
  NeoHookeanParams reference_params;
  auto reference = make_neo_hookean(bar(), kPdMaterial, reference_params);
  constexpr int kSteps = 15;  // 0.25 s: the bar still swinging, where iterations matter
  const Eigen::Matrix3Xd expected = clamped_bar(*reference, kSteps);
  const double motion = rms_distance(expected, bar().rest_positions());
  std::vector<double> errors;
  for (const int iterations : {1, 3, 10, 30, 100}) {
    ProjectiveDynamicsParams params;
    params.iterations = iterations;
    auto pd = make_projective_dynamics(bar(), kPdMaterial, params);
    errors.push_back(rms_distance(clamped_bar(*pd, kSteps), expected) / motion);
    std::cout << "[ iterations ] " << iterations << ": RMS error / motion " << errors.back()
              << "\n";
  }
  // Measured: 0.37, 0.073, 0.062, 0.0617, 0.0617. What remains at convergence is the two
  // materials' difference at this 7 cm sag of a 10 cm bar (corotated against stable
  // neo-Hookean, equal only at small strain), not the iterations'.
  for (std::size_t k = 1; k < errors.size(); ++k) {
    EXPECT_LE(errors[k], errors[k - 1]) << "iterations step " << k;
  }
  EXPECT_GT(errors[0], 2.0 * errors.back());
  EXPECT_LT(errors.back(), 0.07);
  EXPECT_NEAR(errors[3], errors[4], 1e-3);  // 30 iterations: converged
}

/// The bar's top vertices (z = max) with x beyond half its length.
std::vector<int> top_far_vertices() {
  const Eigen::Matrix3Xd& rest = bar().rest_positions();
  const double top = rest.row(2).maxCoeff();
  std::vector<int> vertices;
  for (int v = 0; v < rest.cols(); ++v) {
    if (rest(2, v) > top - 1e-12 && rest(0, v) > 0.05) {
      vertices.push_back(v);
    }
  }
  return vertices;
}

TEST(ProjectiveDynamics, HoldsByMultipliersEqualHoldsByElimination) {
  // The same full holds, once anchoring (eliminated from the factor) and once not (imposed by
  // multipliers on the kept factor): the same step to round-off, the same forces.
  const std::vector<int> pressed = top_far_vertices();
  ASSERT_GE(pressed.size(), 4U);
  const auto run = [&](bool anchors, Eigen::Matrix3Xd* forces) {
    auto pd = make_projective_dynamics(bar(), kPdMaterial, {});
    std::vector<PositionConstraint> holds = pin_min_x_face(bar());
    for (const int v : pressed) {
      holds.push_back({v, bar().rest_positions().col(v), kExact,
                       Eigen::Matrix3d::Identity(), anchors});
    }
    for (int step = 0; step < 20; ++step) {
      for (std::size_t k = holds.size() - pressed.size(); k < holds.size(); ++k) {
        holds[k].target.z() -= 2e-4;  // pressed down 4 mm over the run
      }
      const StepStats stats = pd->step(kPdDt, ramped_gravity(step, holds));
      EXPECT_LT(stats.max_constraint_error, 1e-14);
    }
    *forces = pd->constraint_forces();
    return Eigen::Matrix3Xd(pd->positions());
  };
  Eigen::Matrix3Xd eliminated_forces;
  Eigen::Matrix3Xd multiplier_forces;
  const Eigen::Matrix3Xd eliminated = run(true, &eliminated_forces);
  const Eigen::Matrix3Xd multipliers = run(false, &multiplier_forces);
  EXPECT_LT((eliminated - multipliers).cwiseAbs().maxCoeff(), 1e-12);
  const double force_scale = eliminated_forces.cwiseAbs().maxCoeff();
  ASSERT_GT(force_scale, 1e-3);
  EXPECT_LT((eliminated_forces - multiplier_forces).cwiseAbs().maxCoeff(), 1e-9 * force_scale);
}

TEST(ProjectiveDynamics, ContactComesAndGoesWithoutRefactorising) {
  // Holds along a normal that change every step (a contact patch moving over the surface):
  // the factor made at the first step stays; only the new vertices' columns are solved for.
  // The holds end on their planes and push along their normals only.
  auto pd = make_projective_dynamics(bar(), kPdMaterial, {});
  const std::vector<PositionConstraint> clamp = pin_min_x_face(bar());
  const std::vector<int> top = top_far_vertices();
  const Eigen::Vector3d normal = Eigen::Vector3d(0.2, 0.0, 1.0).normalized();
  int factorizations = 0;
  for (int step = 0; step < 30; ++step) {
    std::vector<PositionConstraint> holds = clamp;
    for (std::size_t k = 0; k < top.size(); ++k) {
      if ((k + static_cast<std::size_t>(step) / 5) % 2 == 0) {
        const int v = top[k];
        holds.push_back({v, bar().rest_positions().col(v) - 1e-3 * normal, kExact,
                         PositionConstraint::along(normal), /*anchors=*/false});
      }
    }
    const StepStats stats = pd->step(kPdDt, ramped_gravity(step, holds));
    ASSERT_TRUE(stats.finite);
    EXPECT_LT(stats.max_constraint_error, 1e-14);
    factorizations += stats.factorizations;
    const Eigen::Matrix3Xd forces = pd->constraint_forces();
    for (std::size_t k = clamp.size(); k < holds.size(); ++k) {
      const Eigen::Vector3d force = forces.col(holds[k].vertex);
      EXPECT_LT(force.cross(normal).norm(), 1e-12 * std::max(1.0, force.norm()));
    }
  }
  EXPECT_EQ(factorizations, 1);
}

TEST(ProjectiveDynamics, APenaltyHoldIsASpringAndAGraspRefactorisesOnce) {
  auto pd = make_projective_dynamics(bar(), kPdMaterial, {});
  std::vector<PositionConstraint> holds = pin_min_x_face(bar());
  const int tip = top_far_vertices().back();
  constexpr double kStiffness = 50.0;  // N/m
  const Eigen::Vector3d anchor = bar().rest_positions().col(tip) + Eigen::Vector3d(0, 0, 0.01);
  holds.push_back({tip, anchor, kStiffness});
  int factorizations = 0;
  for (int step = 0; step < 10; ++step) {
    const StepStats stats = pd->step(kPdDt, ramped_gravity(step, holds));
    factorizations += stats.factorizations;
    const Eigen::Vector3d spring = kStiffness * (anchor - pd->positions().col(tip));
    EXPECT_LT((pd->constraint_forces().col(tip) - spring).norm(), 1e-12 * spring.norm());
  }
  EXPECT_EQ(factorizations, 1);
  // The spring becomes a grasp (an exact anchoring hold): a new eliminated set, one factor;
  // then it holds without another.
  holds.back().stiffness = kExact;
  for (int step = 10; step < 15; ++step) {
    factorizations += pd->step(kPdDt, ramped_gravity(step, holds)).factorizations;
    EXPECT_EQ(pd->positions().col(tip), anchor);
  }
  EXPECT_EQ(factorizations, 2);
}

TEST(ProjectiveDynamics, OneAndTwoThreadsGiveTheSameBitsWhereTheLocalStepRunsInParallel) {
  // Above kParallelElements the element parts are made in parallel and gathered per vertex;
  // below, added as they are made. Both sum each vertex's parts in element order.
  const TetMesh mesh = make_tet_mesh(test::box_tets(20, 15, 10, 0.2, 0.15, 0.1));
  ASSERT_GT(mesh.num_tets(), projective_dynamics::kParallelElements);
  const std::vector<PositionConstraint> clamp = pin_min_x_face(mesh);
  const auto run = [&](int threads) {
    omp_set_num_threads(threads);
    auto pd = make_projective_dynamics(mesh, kPdMaterial, {});
    for (int step = 0; step < 3; ++step) {
      EXPECT_TRUE(pd->step(kPdDt, ramped_gravity(10 + step, clamp)).finite);
    }
    return std::make_pair(Eigen::Matrix3Xd(pd->positions()),
                          Eigen::Matrix3Xd(pd->constraint_forces()));
  };
  const int threads = omp_get_max_threads();
  const auto one = run(1);
  const auto two = run(2);
  omp_set_num_threads(threads);
  EXPECT_EQ(one.first, two.first);
  EXPECT_EQ(one.second, two.second);
}

}  // namespace
}  // namespace softbench
