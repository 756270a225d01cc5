// SPDX-License-Identifier: MIT
#include "models/corotational_fem/corotational_fem.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "models/block_pattern.h"
#include "models/corotational_fem/corotational_fem_model.h"
#include "models/model_registry.h"
#include "tests/model_test_support.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <numeric>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace softbench {
namespace {

using test::kinetic_energy;
using test::no_gravity;
using test::pin_all;
using test::pin_min_x_face;
using test::place_at_rest;

using ::testing::HasSubstr;
using Params = CorotationalFemParams;
using corotational_fem::CorotationalFemModel;

// ---------------------------------------------------------------------------------------------
// Tolerances and settings

/// Forces and stresses of O(1) relative size after a few hundred flops per vertex: round-off.
constexpr double kForceRoundoff = 1e-10;
/// Central differences with step kDifferenceStep on O(0.1 m) positions: truncation
/// ~ h^2 f''' ~ 1e-12 relative, cancellation ~ 1e-16 / h ~ 1e-9 relative.
constexpr double kDifferenceStep = 1e-7;
constexpr double kDifferenceAgreement = 1e-6;
/// "Recovered": RMS distance to the best rigid placement of the rest shape below 1% of the
/// bounding-box diagonal.
constexpr double kRecovered = 0.01;
/// Euler-Bernoulli's tip deflection F L^3 / (3 E I) within 5% on the finest cantilever mesh.
/// Linear tets are too stiff in bending (locking), so the
/// coarse meshes are further off; shear (Timoshenko, ~ +0.8% for 10:1) and the clamp's
/// restrained Poisson contraction are within the tolerance.
constexpr double kBeamTheoryAgreement = 0.05;

/// The thesis's liver material.
const Material kMaterial{3000.0, 0.3, 1060.0};

/// The scenes' step.
constexpr double kFemDt = 1.0 / 60.0;

Params with_solver(Params::LinearSolver solver, double cg_tolerance = 1e-6) {
  Params params;
  params.solver = solver;
  params.cg_tolerance = cg_tolerance;
  params.cg_max_iterations = 5000;
  return params;
}

Params linear() {
  Params params;
  params.formulation = Params::Formulation::kLinear;
  return params;
}

Params svd() {
  Params params;
  params.rotation = Params::Rotation::kSvd;
  return params;
}

/// The quaternion rotation iterated to convergence each step (from any warm start).
Params converged_quaternion() {
  Params params;
  params.rotation = Params::Rotation::kQuaternion;
  params.rotation_iterations = 200;
  params.rotation_tolerance = 1e-14;
  return params;
}

double rms(const Eigen::Matrix3Xd& vectors) {
  return std::sqrt(vectors.colwise().squaredNorm().mean());
}

/// sigma(eps) = 2 mu eps + lambda tr(eps) I.
Eigen::Matrix3d analytic_stress(const Eigen::Matrix3d& strain, const Material& material) {
  const LameParameters lame = lame_parameters(material);
  return 2.0 * lame.mu * strain + lame.lambda * strain.trace() * Eigen::Matrix3d::Identity();
}

/// The shipped liver (scenes/data/liver.msh), found from this file's path so the test does not
/// depend on the working directory.
const TetMesh& shipped_liver() {
  static const TetMesh mesh = make_tet_mesh(
      read_mesh(std::filesystem::path(__FILE__).parent_path() / "../../scenes/data/liver.msh"));
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// Forces, energy and stiffness

TEST(CorotationalFem, UniformDeformationGivesTheAnalyticStressAndForces) {
  // Patch test: x = Q A X + t with A = I + eps (eps symmetric, 1% strains). Every element has the
  // uniform stress sigma(eps) (rotated by Q), so interior vertices feel no force and the nodal
  // forces' first moment is sum_a f_a X_a^T = -V Q sigma (sum_a b_a X_a^T = I per element).
  const TetMesh mesh = make_tet_mesh(test::box_tets(3, 3, 3, 0.12, 0.09, 0.09));
  Eigen::Matrix3d strain;
  strain << 0.010, 0.002, -0.003,  //
      0.002, -0.005, 0.004,        //
      -0.003, 0.004, 0.008;
  const Eigen::Matrix3d stretch = Eigen::Matrix3d::Identity() + strain;
  const Eigen::Matrix3d sigma = analytic_stress(strain, kMaterial);
  const double volume = mesh_volume(mesh);
  const double stress_scale = sigma.norm() * volume;
  const Eigen::Matrix3d quarter_turn =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d(1, 2, 3).normalized())
          .toRotationMatrix();

  struct Case {
    Params params;
    Eigen::Matrix3d rotation;
  };
  for (const Case& c : {Case{linear(), Eigen::Matrix3d::Identity()}, Case{svd(), quarter_turn},
                        Case{converged_quaternion(), quarter_turn}}) {
    CorotationalFemModel model(mesh, kMaterial, c.params);
    const Eigen::Matrix3Xd moved =
        (c.rotation * stretch * mesh.rest_positions()).colwise() + Eigen::Vector3d(0.1, -0.2, 0.3);
    model.set_state(moved, Eigen::Matrix3Xd::Zero(3, mesh.num_vertices()));
    model.update_deformations();
    const Eigen::Matrix3Xd forces = model.elastic_forces();

    const Eigen::Matrix3d moment = forces * mesh.rest_positions().transpose();
    EXPECT_TRUE(moment.isApprox(-volume * c.rotation * sigma, kForceRoundoff)) << moment;
    EXPECT_LT(forces.rowwise().sum().norm(), kForceRoundoff * stress_scale);
    const Eigen::Matrix<double, 3, 2> box = bounding_box(mesh.rest_positions());
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const Eigen::Vector3d x = mesh.rest_positions().col(v);
      const bool interior =
          ((x - box.col(0)).array() > 1e-9).all() && ((box.col(1) - x).array() > 1e-9).all();
      if (interior) {
        EXPECT_LT(forces.col(v).norm(), kForceRoundoff * stress_scale) << "vertex " << v;
      }
    }
    // Energy density mu |eps|^2 + lambda/2 tr(eps)^2 over the volume.
    const LameParameters lame = lame_parameters(kMaterial);
    const double energy =
        volume
        * (lame.mu * strain.squaredNorm() + 0.5 * lame.lambda * strain.trace() * strain.trace());
    EXPECT_NEAR(model.elastic_energy(), energy, kForceRoundoff * energy);
  }
}

TEST(CorotationalFem, RigidQuarterTurnProducesNoElasticForceWhenCorotational) {
  const TetMesh& mesh = test::liver_like_box();
  const Eigen::Matrix3Xd turned =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix()
      * mesh.rest_positions();
  // The force a 1% strain would cause, as the scale against which zero is judged.
  const double force_scale = kMaterial.young_modulus * 0.01 * 0.05 * 0.05;
  for (const Params& params : {svd(), converged_quaternion()}) {
    CorotationalFemModel model(mesh, kMaterial, params);
    model.set_state(turned, Eigen::Matrix3Xd::Zero(3, mesh.num_vertices()));
    model.update_deformations();
    EXPECT_LT(model.elastic_forces().cwiseAbs().maxCoeff(), kForceRoundoff * force_scale);
    EXPECT_LT(model.elastic_energy(), kForceRoundoff * force_scale * 0.05);
  }
}

TEST(CorotationalFem, RigidQuarterTurnProducesLargeElasticForcesWhenLinear) {
  // Linear FEM sees the rotation x = Q X as the strain sym(Q) - I = diag(-1, -1, 0): a 100%
  // compression in the plane of the turn, with forces far above those of a 1% strain.
  const TetMesh& mesh = test::liver_like_box();
  const Eigen::Matrix3Xd turned =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix()
      * mesh.rest_positions();
  const double force_scale = kMaterial.young_modulus * 0.01 * 0.05 * 0.05;
  CorotationalFemModel model(mesh, kMaterial, linear());
  model.set_state(turned, Eigen::Matrix3Xd::Zero(3, mesh.num_vertices()));
  model.update_deformations();
  EXPECT_GT(model.elastic_forces().cwiseAbs().maxCoeff(), 10.0 * force_scale);
  EXPECT_GT(model.elastic_energy(), 0.0);
}

/// A small mesh at a random, non-inverted deformation of up to ~15% (and a rotation).
struct DeformedMesh {
  TetMesh mesh = make_tet_mesh(test::box_tets(2, 1, 1, 0.2, 0.1, 0.1));
  Eigen::Matrix3Xd positions;
  DeformedMesh() {
    std::mt19937 random(11);
    std::uniform_real_distribution<double> jitter(-0.015, 0.015);
    positions = Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix()
                * mesh.rest_positions();
    for (int k = 0; k < positions.size(); ++k) {
      positions(k) += jitter(random);
    }
  }
};

TEST(CorotationalFem, ForcesAreTheNegativeGradientOfTheEnergy) {
  // With the exact polar rotation the corotational force is the energy's exact gradient.
  const DeformedMesh deformed;
  for (const Params& params : {linear(), svd()}) {
    CorotationalFemModel model(deformed.mesh, kMaterial, params);
    const Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, deformed.mesh.num_vertices());
    model.set_state(deformed.positions, zero);
    model.update_deformations();
    const Eigen::Matrix3Xd forces = model.elastic_forces();
    const double scale = forces.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0.0);
    for (int k = 0; k < deformed.positions.size(); ++k) {
      Eigen::Matrix3Xd plus = deformed.positions;
      Eigen::Matrix3Xd minus = deformed.positions;
      plus(k) += kDifferenceStep;
      minus(k) -= kDifferenceStep;
      model.set_state(plus, zero);
      const double energy_plus = model.elastic_energy();
      model.set_state(minus, zero);
      const double energy_minus = model.elastic_energy();
      const double gradient = (energy_plus - energy_minus) / (2.0 * kDifferenceStep);
      EXPECT_NEAR(forces(k), -gradient, kDifferenceAgreement * scale) << "entry " << k;
    }
  }
}

/// -(f(x + h e_k) - f(x - h e_k)) / 2h for every k, the rotations recomputed or held.
Eigen::MatrixXd force_jacobian(CorotationalFemModel& model,
                               const Eigen::Matrix3Xd& positions,
                               bool hold_rotations) {
  const Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, positions.cols());
  Eigen::MatrixXd jacobian(positions.size(), positions.size());
  for (int k = 0; k < positions.size(); ++k) {
    Eigen::Matrix3Xd plus = positions;
    Eigen::Matrix3Xd minus = positions;
    plus(k) += kDifferenceStep;
    minus(k) -= kDifferenceStep;
    model.set_state(plus, zero);
    model.update_deformations(hold_rotations);
    const Eigen::Matrix3Xd forces_plus = model.elastic_forces();
    model.set_state(minus, zero);
    model.update_deformations(hold_rotations);
    const Eigen::Matrix3Xd forces_minus = model.elastic_forces();
    jacobian.col(k) = -(forces_plus - forces_minus).reshaped() / (2.0 * kDifferenceStep);
  }
  return jacobian;
}

TEST(CorotationalFem, StiffnessIsTheDerivativeOfTheForcesForLinearFem) {
  const DeformedMesh deformed;
  CorotationalFemModel model(deformed.mesh, kMaterial, linear());
  const Eigen::MatrixXd jacobian = force_jacobian(model, deformed.positions, false);
  const Eigen::MatrixXd stiffness = Eigen::MatrixXd(model.stiffness_matrix());
  EXPECT_LT((stiffness - jacobian).cwiseAbs().maxCoeff(),
            kDifferenceAgreement * stiffness.cwiseAbs().maxCoeff());
  EXPECT_TRUE(stiffness.isApprox(stiffness.transpose(), kForceRoundoff));
}

TEST(CorotationalFem, StiffnessIsTheDerivativeOfTheRotatedLinearForcesWithRotationsHeld) {
  // Warped stiffness: with every element's R frozen, f_a = -R K0 (R^T x - X) is linear in x and
  // K(R) is its exact derivative.
  const DeformedMesh deformed;
  for (const Params& params : {svd(), Params{}}) {
    CorotationalFemModel model(deformed.mesh, kMaterial, params);
    model.set_state(deformed.positions, Eigen::Matrix3Xd::Zero(3, deformed.mesh.num_vertices()));
    model.update_deformations();
    const Eigen::MatrixXd stiffness = Eigen::MatrixXd(model.stiffness_matrix());
    const Eigen::MatrixXd jacobian =
        force_jacobian(model, deformed.positions, /*hold_rotations=*/true);
    EXPECT_LT((stiffness - jacobian).cwiseAbs().maxCoeff(),
              kDifferenceAgreement * stiffness.cwiseAbs().maxCoeff());
  }
}

// ---------------------------------------------------------------------------------------------
// Constraints and reactions

TEST(CorotationalFem, PinnedVerticesNeverMoveWithAnySolver) {
  const TetMesh& mesh = test::liver_like_box();
  const std::vector<PositionConstraint> pins = pin_min_x_face(mesh);
  StepInput input;
  input.constraints = pins;
  for (const Params::LinearSolver solver :
       {Params::LinearSolver::kCholmod, Params::LinearSolver::kConjugateGradient,
        Params::LinearSolver::kCholeskyPcg}) {
    auto body = make_corotational_fem(mesh, kMaterial, with_solver(solver));
    for (int step = 0; step < 30; ++step) {
      const StepStats stats = body->step(kFemDt, input);
      ASSERT_TRUE(stats.finite);
      EXPECT_EQ(stats.max_constraint_error, 0.0);
      for (const PositionConstraint& pin : pins) {
        // Bit-exact: the position is the target itself, not a solve's approximation of it.
        ASSERT_EQ(body->positions().col(pin.vertex), pin.target);
        ASSERT_TRUE(body->velocities().col(pin.vertex).isZero(0.0));
      }
    }
    EXPECT_GT((body->positions() - mesh.rest_positions()).norm(), 0.0);  // gravity acts
  }
}

TEST(CorotationalFem, ReactionsBalanceGravityAtRest) {
  const TetMesh mesh = make_tet_mesh(test::box_tets(3, 2, 2, 0.15, 0.1, 0.1));
  const Eigen::VectorXd masses = lumped_masses(mesh, kMaterial.density);
  const std::vector<PositionConstraint> pins = pin_min_x_face(mesh);
  StepInput input;
  input.constraints = pins;
  for (const Params::LinearSolver solver :
       {Params::LinearSolver::kCholmod, Params::LinearSolver::kConjugateGradient}) {
    Params params = with_solver(solver, /*cg_tolerance=*/1e-12);
    params.rayleigh_mass = 2.0;  // 1/s: settles in a few hundred steps
    auto body = make_corotational_fem(mesh, kMaterial, params);
    test::expect_reactions_balance_weight_at_rest(*body, masses, input, pins);
  }
}

TEST(CorotationalFem, PenaltyConstraintsPullTowardTheirTargetAndReportTheirError) {
  const TetMesh mesh = make_tet_mesh(test::single_tet());
  auto body = make_corotational_fem(mesh, kMaterial, Params{});
  const Eigen::Vector3d target = mesh.rest_positions().col(3) + Eigen::Vector3d(0.0, 0.0, 0.01);
  const std::vector<PositionConstraint> grab{{3, target, 1000.0}};
  const StepStats stats = body->step(1e-3, no_gravity(grab));
  const Eigen::Vector3d gap = target - body->positions().col(3);
  EXPECT_GT(body->velocities()(2, 3), 0.0);  // pulled up
  EXPECT_NEAR(stats.max_constraint_error, gap.norm(), test::kRoundoff);
  EXPECT_GT(stats.max_constraint_error, 0.0);
  EXPECT_TRUE(body->constraint_forces().col(3).isApprox(1000.0 * gap, test::kRoundoff));
}

// ---------------------------------------------------------------------------------------------
// Linear solvers

TEST(CorotationalFem, CholmodAndIterativeSolversAgreeToTheCgToleranceOnOneStep) {
  const TetMesh& mesh = test::liver_like_box();
  const std::vector<PositionConstraint> pins = pin_min_x_face(mesh);
  StepInput input;
  input.constraints = pins;
  constexpr double kCgTolerance = 1e-8;
  auto direct = make_corotational_fem(mesh, kMaterial, with_solver(Params::LinearSolver::kCholmod));
  const StepStats direct_stats = direct->step(1.0 / 30.0, input);
  EXPECT_EQ(direct_stats.factorizations, 1);
  EXPECT_EQ(direct_stats.iterations, 0);
  EXPECT_LT(direct_stats.residual, 1e-12);  // a backward-stable direct solve

  Params jacobi = with_solver(Params::LinearSolver::kConjugateGradient, kCgTolerance);
  jacobi.preconditioner = Params::Preconditioner::kJacobi;
  for (const Params& params :
       {with_solver(Params::LinearSolver::kConjugateGradient, kCgTolerance), jacobi,
        with_solver(Params::LinearSolver::kCholeskyPcg, kCgTolerance)}) {
    auto iterative = make_corotational_fem(mesh, kMaterial, params);
    const StepStats stats = iterative->step(1.0 / 30.0, input);
    EXPECT_GT(stats.iterations, 0);
    EXPECT_LE(stats.residual, kCgTolerance);
    // CG bounds the residual; the error is at most cond(A) times that. A = M + dt^2 K here
    // (5 cm cells, dt = 1/30 s) has cond(A) < 1e3, so the solutions agree to 1e3 x tolerance.
    constexpr double kConditionBound = 1e3;
    EXPECT_LT((direct->velocities() - iterative->velocities()).norm(),
              kConditionBound * kCgTolerance * direct->velocities().norm());
  }
}

TEST(CorotationalFem, CholeskyPcgReusesItsFactorWhileItPreconditionsWell) {
  const TetMesh& mesh = test::liver_like_box();
  const std::vector<PositionConstraint> pins = pin_min_x_face(mesh);
  StepInput input;
  input.constraints = pins;
  Params params = with_solver(Params::LinearSolver::kCholeskyPcg, 1e-8);
  params.refresh_iterations = 5;
  auto body = make_corotational_fem(mesh, kMaterial, params);
  const StepStats first = body->step(kFemDt, input);
  EXPECT_EQ(first.factorizations, 1);  // no factor yet
  EXPECT_LE(first.iterations, 2);      // preconditioned by its own matrix's factor
  int factorizations = 0;
  constexpr int kSteps = 60;
  for (int step = 0; step < kSteps; ++step) {
    const StepStats stats = body->step(kFemDt, input);
    ASSERT_TRUE(stats.finite);
    EXPECT_LE(stats.residual, 1e-8);
    factorizations += stats.factorizations;
  }
  EXPECT_LT(factorizations, kSteps / 2);  // the factor outlives most steps
}

TEST(CorotationalFem, ConjugateGradientReportsHittingItsIterationCap) {
  Params params = with_solver(Params::LinearSolver::kConjugateGradient, 1e-14);
  params.cg_max_iterations = 3;
  // Pinned at one face: a free body under gravity falls as a whole, which the solver's coarse
  // level solves exactly before its first iteration.
  const std::vector<PositionConstraint> pins = pin_min_x_face(test::liver_like_box());
  StepInput input;
  input.constraints = pins;
  auto body = make_corotational_fem(test::liver_like_box(), kMaterial, params);
  const StepStats stats = body->step(kFemDt, input);
  EXPECT_EQ(stats.iterations, 3);
  EXPECT_EQ(stats.truncated_solves, 1);  // stopped by the cap, not by the tolerance
  EXPECT_GT(stats.residual, 1e-14);
  EXPECT_TRUE(stats.finite);
  // With room for it, the same solve meets its tolerance.
  params.cg_max_iterations = 5000;
  params.cg_tolerance = 1e-8;
  EXPECT_EQ(make_corotational_fem(test::liver_like_box(), kMaterial, params)
                ->step(kFemDt, input)
                .truncated_solves,
            0);
}

TEST(CorotationalFem, QuaternionAndSvdRotationsGiveTheSameMotionWhenConverged) {
  const TetMesh& mesh = test::liver_like_box();
  const std::vector<PositionConstraint> pins = pin_min_x_face(mesh);
  StepInput input;
  input.constraints = pins;
  Params by_svd = svd();
  Params by_quaternion = converged_quaternion();
  by_svd.cg_tolerance = by_quaternion.cg_tolerance = 1e-12;
  auto a = make_corotational_fem(mesh, kMaterial, by_svd);
  auto b = make_corotational_fem(mesh, kMaterial, by_quaternion);
  for (int step = 0; step < 30; ++step) {
    a->step(kFemDt, input);
    b->step(kFemDt, input);
  }
  const double motion = rms(a->positions() - mesh.rest_positions());
  ASSERT_GT(motion, 0.01);  // it sagged by centimetres: the elements rotated
  // Both rotations are exact to ~1e-13 and CG to 1e-12: the trajectories agree to round-off
  // amplified over 30 steps.
  EXPECT_LT(rms(a->positions() - b->positions()), 1e-9 * motion);
}

// ---------------------------------------------------------------------------------------------
// Acceptance: cantilever, recovery from a squash, determinism

/// The tip deflection of a 10:1:1 cantilever (L = 1 m, 0.1 x 0.1 m section) clamped at x = 0
/// under a small tip load, relative to Euler-Bernoulli's F L^3 / (3 E I) minus one.
double cantilever_error(int nx, int ny, int nz) {
  constexpr double kLength = 1.0;
  constexpr double kSide = 0.1;
  const TetMesh mesh = make_tet_mesh(test::box_tets(nx, ny, nz, kLength, kSide, kSide));
  const std::vector<PositionConstraint> clamp = pin_min_x_face(mesh);
  // 1e-4 N down: a deflection of 1.3 mm, 0.13% of the length, so geometric nonlinearity is
  // negligible. Spread over the tip face by area (each face cell's share to its 4 corners).
  constexpr double kLoad = 1e-4;
  Eigen::Matrix3Xd loads = Eigen::Matrix3Xd::Zero(3, mesh.num_vertices());
  std::vector<int> tip;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d x = mesh.rest_positions().col(v);
    if (x.x() >= kLength - 1e-12) {
      tip.push_back(v);
      const bool edge_y = x.y() < 1e-12 || x.y() > kSide - 1e-12;
      const bool edge_z = x.z() < 1e-12 || x.z() > kSide - 1e-12;
      const double cells_touching = (edge_y ? 1.0 : 2.0) * (edge_z ? 1.0 : 2.0);
      loads(2, v) = -kLoad * cells_touching / (4.0 * ny * nz);
    }
  }
  // Static equilibrium by the dynamic model with a huge step: M / dt^2 ~ 1e-9 of K, so each
  // backward Euler step is a Newton step on f(x) + F = 0 (CHOLMOD, exact). "Rest": the last
  // step moved the tip by less than kRest of its deflection (a far smaller error than the 5%
  // being tested; in practice the second step already confirms the first).
  constexpr double kRest = 1e-6;
  Params params = with_solver(Params::LinearSolver::kCholmod);
  auto body = make_corotational_fem(mesh, kMaterial, params);
  StepInput input = no_gravity(clamp);
  input.external_forces = &loads;
  constexpr double kStaticDt = 1e3;
  const auto tip_deflection = [&] {
    double sum = 0.0;
    for (const int v : tip) {
      sum += body->positions()(2, v) - mesh.rest_positions()(2, v);
    }
    return sum / static_cast<double>(tip.size());
  };
  double previous = 0.0;
  double deflection = 0.0;
  for (int step = 0; step < 20; ++step) {
    EXPECT_TRUE(body->step(kStaticDt, input).finite);
    deflection = tip_deflection();
    if (step > 0 && std::abs(deflection - previous) < kRest * std::abs(deflection)) {
      break;
    }
    previous = deflection;
  }
  const double inertia = kSide * kSide * kSide * kSide / 12.0;
  const double beam_theory =
      -kLoad * kLength * kLength * kLength / (3.0 * kMaterial.young_modulus * inertia);
  return deflection / beam_theory - 1.0;
}

TEST(CorotationalFem, CantileverDeflectionConvergesToEulerBernoulliUnderRefinement) {
  // Kuhn-split cubes of side 0.1 / n, refined along all three axes. Linear tets lock in
  // bending and converge slowly (measured: -78%, -49%, -21%, -11% at n = 1, 2, 4, 6; -4.1% at
  // n = 10, 36k unknowns, ~2.5 s of the test's time).
  const std::vector<std::array<int, 3>> meshes{{10, 1, 1}, {20, 2, 2}, {40, 4, 4}, {100, 10, 10}};
  double previous = 0.0;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    const auto [nx, ny, nz] = meshes[k];
    const double error = cantilever_error(nx, ny, nz);
    std::cout << "[ cantilever ] " << nx << "x" << ny << "x" << nz
              << ": tip deflection / Euler-Bernoulli - 1 = " << error << "\n";
    if (k > 0) {
      EXPECT_LT(std::abs(error), std::abs(previous)) << "refinement " << k;
    }
    if (k + 1 == meshes.size()) {
      EXPECT_LT(std::abs(error), kBeamTheoryAgreement);
    }
    previous = error;
  }
}

/// The rotation and translation best placing `rest` on `current` (Kabsch), applied to `rest`.
Eigen::Matrix3Xd best_rigid_placement(const Eigen::Matrix3Xd& rest,
                                      const Eigen::Matrix3Xd& current) {
  const Eigen::Vector3d rest_centre = rest.rowwise().mean();
  const Eigen::Vector3d current_centre = current.rowwise().mean();
  const Eigen::Matrix3d covariance =
      (current.colwise() - current_centre) * (rest.colwise() - rest_centre).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
  correction(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d rotation = svd.matrixU() * correction * svd.matrixV().transpose();
  return (rotation * (rest.colwise() - rest_centre)).colwise() + current_centre;
}

TEST(CorotationalFem, LiverSquashedFlatRecoversItsRestShape) {
  // Every vertex projected onto the plane through the centroid normal to z (the liver's thinnest
  // axis): every element degenerate (F = I - n n^T). Released with no gravity or pins, the
  // corotational elements push back along n and the liver regains its shape.
  const TetMesh& mesh = shipped_liver();
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const Eigen::Matrix<double, 3, 2> box = bounding_box(rest);
  const double diagonal = (box.col(1) - box.col(0)).norm();
  Eigen::Matrix3Xd flat = rest;
  flat.row(2).setConstant(rest.row(2).mean());

  for (const Params& params : {Params{}, svd()}) {
    auto body = make_corotational_fem(mesh, kMaterial, params);
    place_at_rest(*body, flat);
    ASSERT_TRUE(body->positions().allFinite());
    ASSERT_LT(std::abs(mesh_volume(mesh, body->positions())), 1e-12);
    const double squashed = rms(body->positions() - rest) / diagonal;
    constexpr int kSteps = 120;  // 2 s
    for (int step = 0; step < kSteps; ++step) {
      ASSERT_TRUE(body->step(kFemDt, no_gravity()).finite) << "step " << step;
    }
    const double residual =
        rms(body->positions() - best_rigid_placement(rest, body->positions())) / diagonal;
    std::cout << "[ squash ] rotation " << body->parameters()["rotation"] << ": RMS " << squashed
              << " of the diagonal when flat, " << residual << " after 2 s\n";
    EXPECT_LT(residual, kRecovered);
    EXPECT_NEAR(mesh_volume(mesh, body->positions()) / mesh_volume(mesh), 1.0, kRecovered);
  }
}

TEST(CorotationalFem, ResultsDoNotDependOnTheThreadCount) {
  // Large enough that every loop may run parallel (elements, gathers, products, the sweeps'
  // two parts). ThreadChoice runs the first two steps on one thread and the third on the
  // threads (its first try of them).
  const TetMesh mesh = make_tet_mesh(test::box_tets(16, 12, 12, 0.40, 0.30, 0.30));
  ASSERT_GE(mesh.num_vertices(), CorotationalFemModel::kThreadedVertices);
  const std::vector<PositionConstraint> pins = pin_min_x_face(mesh);
  StepInput input;
  input.constraints = pins;
  const int threads_before = omp_get_max_threads();
  std::vector<Eigen::Matrix3Xd> results;
  for (const int threads : {1, 2}) {
    omp_set_num_threads(threads);
    auto body = make_corotational_fem(mesh, kMaterial, Params{});
    for (int step = 0; step < 3; ++step) {
      body->step(kFemDt, input);
    }
    results.push_back(body->positions());
  }
  omp_set_num_threads(threads_before);
  EXPECT_TRUE(results[0] == results[1]);  // bit-identical
  EXPECT_NE(results[0], mesh.rest_positions());
}

TEST(CorotationalFem, ResultsDoNotDependOnHowTheMeshNumbersItsVertices) {
  // The model numbers vertices and elements its own way (renumbered_vertices.h).
  test::expect_motion_independent_of_vertex_numbering([](const TetMesh& mesh) {
    return make_corotational_fem(mesh, kMaterial, with_solver(Params::LinearSolver::kCholmod));
  });
}

// ---------------------------------------------------------------------------------------------
// Parameters

TEST(CorotationalFem, RejectsABadParameterNamingItsKey) {
  const ModelInfo& info = builtin_models().at("corotational_fem");
  const nlohmann::json bad_solver = {{"solver", "lu"}};
  EXPECT_THAT(
      [&] {
        info.create(test::liver_like_box(), kMaterial, bad_solver, {"scene.json", "/models/fem"});
      },
      ::testing::ThrowsMessage<InputError>(HasSubstr("/models/fem/solver")));
  const nlohmann::json bad_tolerance = {{"cg_tolerance", 0.0}};
  EXPECT_THROW(
      info.create(test::liver_like_box(), kMaterial, bad_tolerance, {"scene.json", "/models/fem"}),
      InputError);
  Params negative;
  negative.rayleigh_stiffness = -1.0;
  EXPECT_THROW(make_corotational_fem(test::liver_like_box(), kMaterial, negative), InputError);
}

TEST(CorotationalFem, ForcesAreTheExactGradientOfTheEnergyWithSvdRotations) {
  // The contract suite checks every model's default forces against its energy; the default
  // warm-started quaternion rotations converge over steps, the SVD rotations are exact, and so
  // must the gradient be: to the central difference's truncation (1e-7 relative).
  const TetMesh mesh = make_tet_mesh(test::box_tets(3, 2, 2, 0.12, 0.08, 0.08));
  CorotationalFemParams params;
  params.rotation = CorotationalFemParams::Rotation::kSvd;
  const auto body = make_corotational_fem(mesh, Material{3000.0, 0.3, 1060.0}, params);
  Eigen::Matrix3Xd x = mesh.rest_positions();
  for (Eigen::Index v = 0; v < x.cols(); ++v) {
    const Eigen::Vector3d p = x.col(v);
    x.col(v) += Eigen::Vector3d(0.1 * p.y() + 0.05 * p.z(), p.x() * p.z(), -0.06 * p.x());
  }
  test::expect_forces_match_energy_gradient(*body, x, 1e-7);
}

}  // namespace
}  // namespace softbench
