// SPDX-License-Identifier: MIT
// The Bullet baselines (models/bullet/): agreement with the corotational FEM under matched
// material, exact pins, the zero-motion trap, instability reported as a result, reactions,
// parameters. The SoftBody contract suite covers them too.
#include "geometry/input_error.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "models/bullet/bullet_soft_body.h"
#include "models/model_registry.h"
#include "tests/model_test_support.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace softbench {
namespace {

using test::pin_min_x_face;

using ::testing::HasSubstr;
using DeformableParams = BulletDeformableParams;

constexpr double kBulletDt = 1.0 / 60.0;
/// Bullet's step moves a held node to its target by x += dt (target - x) / dt: round-off of the
/// order of the coordinates' ulp, before the adapter writes the target itself.
constexpr double kIntegrationRoundoff = 1e-15;

const Material kLiver{3000.0, 0.3, 1060.0};

/// A 12 x 8 x 8 cm box of 3 x 2 x 2 cells.
const TetMesh& small_box() {
  static const TetMesh mesh = make_tet_mesh(test::box_tets(3, 2, 2, 0.12, 0.08, 0.08));
  return mesh;
}

std::vector<int> max_x_face(const TetMesh& mesh) {
  const double max_x = mesh.rest_positions().row(0).maxCoeff();
  std::vector<int> tip;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.rest_positions()(0, v) >= max_x - 1e-12) {
      tip.push_back(v);
    }
  }
  return tip;
}

DeformableParams deformable(DeformableParams::Force force, bool implicit) {
  DeformableParams params;
  params.force = force;
  params.implicit = implicit;
  return params;
}

/// Both Bullet models with their defaults, for the properties they share.
std::vector<std::unique_ptr<SoftBody>> both_models(const TetMesh& mesh, const Material& material) {
  std::vector<std::unique_ptr<SoftBody>> bodies;
  bodies.push_back(make_bullet_softbody(mesh, material, BulletSoftBodyParams{}));
  bodies.push_back(make_bullet_deformable(mesh, material, DeformableParams{}));
  return bodies;
}

/// The mean vertical (z) displacement of `vertices`, m (negative: down).
double mean_z_displacement(const SoftBody& body, const TetMesh& mesh, const std::vector<int>& vs) {
  double sum = 0.0;
  for (int v : vs) {
    sum += body.positions()(2, v) - mesh.rest_positions()(2, v);
  }
  return sum / static_cast<double>(vs.size());
}

/// Steps until every vertex has stayed slower than `rest_speed` for a second (a turning point
/// of an oscillation does not count), at most `max_steps`. Returns whether it came to rest.
bool run_to_rest(SoftBody& body, const StepInput& input, double dt, int max_steps) {
  constexpr double kRestSpeed = 2e-3;  // m/s: 0.03 mm per step at 1/60 s
  const int window = static_cast<int>(std::ceil(1.0 / dt));
  int slow_steps = 0;
  for (int step = 0; step < max_steps; ++step) {
    if (!body.step(dt, input).finite) {
      return false;
    }
    const double speed = body.velocities().colwise().norm().maxCoeff();
    slow_steps = speed < kRestSpeed ? slow_steps + 1 : 0;
    if (slow_steps >= window) {
      return true;
    }
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// Agreement with the corotational FEM

/// Tip sags of bullet_deformable (neo-Hookean, implicit, dt 1/60) and corotational_fem on a bar
/// clamped at x = 0 under gravity, both run to rest, in m.
struct Sags {
  double fem = 0.0;
  double bullet = 0.0;
};
Sags clamped_bar_sags(const TetMesh& bar, const DeformableParams& bullet_params) {
  const Material material{30000.0, 0.3, 1000.0};
  const std::vector<PositionConstraint> clamp = pin_min_x_face(bar);
  const std::vector<int> tip = max_x_face(bar);
  StepInput input;
  input.constraints = clamp;
  // Damping only speeds up settling; neither model's static equilibrium depends on it.
  const auto fem = builtin_models()
                       .at("corotational_fem")
                       .create(bar, material, {{"rayleigh_mass", 2.0}}, ParamSource{});
  EXPECT_TRUE(run_to_rest(*fem, input, kBulletDt, 1500)) << "corotational_fem";
  const auto bullet = make_bullet_deformable(bar, material, bullet_params);
  EXPECT_TRUE(run_to_rest(*bullet, input, kBulletDt, 1500)) << "bullet_deformable";
  return {-mean_z_displacement(*fem, bar, tip), -mean_z_displacement(*bullet, bar, tip)};
}

TEST(BulletDeformable, NeoHookeanSagOfAClampedBarAgreesWithCorotationalFemWithin15Percent) {
  if (!builtin_models().contains("corotational_fem")) {
    GTEST_SKIP() << "corotational_fem is not registered in this build";
  }
  // 0.2 x 0.04 x 0.04 m, E 30 kPa, nu 0.3, 1000 kg/m^3: the tip sags ~15 cm, large rotations.
  const TetMesh bar = make_tet_mesh(test::box_tets(10, 2, 2, 0.2, 0.04, 0.04));
  DeformableParams params;
  params.damping = 0.2;  // s: settles in ~10 s of simulated time instead of ~30
  const Sags sags = clamped_bar_sags(bar, params);
  std::cout << "[ bar sag ] corotational_fem " << sags.fem << " m, bullet_deformable "
            << sags.bullet << " m\n";
  ASSERT_GT(sags.fem, 0.05);
  EXPECT_NEAR(sags.bullet / sags.fem, 1.0, 0.15);
}

TEST(BulletDeformable, MatchedLameParametersGiveTheFemSmallStrainSagAndDirectOnesASofterOne) {
  if (!builtin_models().contains("corotational_fem")) {
    GTEST_SKIP() << "corotational_fem is not registered in this build";
  }
  // A stubby bar (0.2 x 0.1 x 0.1 m) sagging a few cm: small strains, where Bullet's stable
  // neo-Hookean with the scene's mu and lambda as they are behaves like E_eff = 0.73 E.
  const TetMesh bar = make_tet_mesh(test::box_tets(6, 3, 3, 0.2, 0.1, 0.1));
  DeformableParams matched;
  matched.damping = 0.2;
  DeformableParams direct = matched;
  direct.lame_mapping = DeformableParams::LameMapping::kDirect;
  const Sags with_matched = clamped_bar_sags(bar, matched);
  const double direct_sag = clamped_bar_sags(bar, direct).bullet;
  std::cout << "[ stubby bar sag ] corotational_fem " << with_matched.fem
            << " m, bullet_deformable matched " << with_matched.bullet << " m, direct "
            << direct_sag << " m\n";
  constexpr double kSmallStrainAgreement = 0.05;  // measured: 2% (same mesh, same locking)
  EXPECT_NEAR(with_matched.bullet / with_matched.fem, 1.0, kSmallStrainAgreement);
  EXPECT_GT(direct_sag / with_matched.fem, 1.2);  // 1/0.73 = 1.37 in the linear limit
}

// ---------------------------------------------------------------------------------------------
// Constraints

TEST(Bullet, PinnedNodesNeverMoveInEitherModel) {
  const std::vector<PositionConstraint> pins = pin_min_x_face(small_box());
  StepInput input;
  input.constraints = pins;
  for (const auto& body : both_models(small_box(), kLiver)) {
    for (int step = 0; step < 30; ++step) {
      const StepStats stats = body->step(kBulletDt, input);
      ASSERT_TRUE(stats.finite) << body->name();
      EXPECT_EQ(stats.max_constraint_error, 0.0);
      EXPECT_LE(stats.residual, kIntegrationRoundoff) << body->name();  // Bullet's own drift
      for (const PositionConstraint& pin : pins) {
        ASSERT_EQ(body->positions().col(pin.vertex), pin.target) << body->name();
        ASSERT_TRUE(body->velocities().col(pin.vertex).isZero(0.0)) << body->name();
      }
    }
    EXPECT_GT((body->positions() - small_box().rest_positions()).norm(), 1e-3) << body->name();
  }
}

TEST(Bullet, MovingPinsCarryTheirNodesAndReleasedNodesFallAgain) {
  // A grasp: one corner pulled up 1 mm per step for 10 steps, then let go.
  const TetMesh& box = small_box();
  const int corner = box.num_vertices() - 1;
  for (const auto& body : both_models(box, kLiver)) {
    std::vector<PositionConstraint> grasp{{corner, box.rest_positions().col(corner), kExact}};
    StepInput input;
    input.gravity.setZero();
    input.constraints = grasp;
    for (int step = 1; step <= 10; ++step) {
      grasp[0].target.z() = box.rest_positions()(2, corner) + 1e-3 * step;
      ASSERT_TRUE(body->step(kBulletDt, input).finite);
      ASSERT_EQ(body->positions().col(corner), grasp[0].target) << body->name();
      EXPECT_NEAR(body->velocities()(2, corner), 1e-3 / kBulletDt, 1e-12) << body->name();
    }
    input.constraints = {};
    input.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
    const double held_at = body->positions()(2, corner);
    for (int step = 0; step < 10; ++step) {
      ASSERT_TRUE(body->step(kBulletDt, input).finite);
    }
    // Its mass is back: gravity and the body's elasticity move it.
    EXPECT_LT(body->positions()(2, corner), held_at - 1e-3) << body->name();
  }
}

TEST(BulletDeformable, PenaltyConstraintsPullTowardTheirTargetAndReportTheirError) {
  const TetMesh mesh = make_tet_mesh(test::single_tet());
  for (const bool implicit : {true, false}) {
    auto body = make_bullet_deformable(mesh, kLiver,
                                       deformable(DeformableParams::Force::kNeoHookean, implicit));
    const Eigen::Vector3d target = mesh.rest_positions().col(3) + Eigen::Vector3d(0, 0, 0.01);
    const std::vector<PositionConstraint> grab{{3, target, 1000.0}};
    StepInput input;
    input.gravity.setZero();
    input.constraints = grab;
    const StepStats stats = body->step(1e-3, input);
    ASSERT_TRUE(stats.finite);
    const Eigen::Vector3d gap = target - body->positions().col(3);
    EXPECT_GT(body->velocities()(2, 3), 0.0) << "implicit " << implicit;
    EXPECT_DOUBLE_EQ(stats.max_constraint_error, gap.norm());
    EXPECT_GT(stats.max_constraint_error, 0.0);
    EXPECT_TRUE(body->constraint_forces().col(3).isApprox(1000.0 * gap, 1e-12));
  }
}

TEST(Bullet, ReactionsBalanceTheWeightAtRest) {
  const TetMesh& box = small_box();
  const double weight = lumped_masses(box, kLiver.density).sum() * 9.81;
  const std::vector<PositionConstraint> pins = pin_min_x_face(box);
  StepInput input;
  input.constraints = pins;
  BulletSoftBodyParams damped;
  damped.damping = 0.05;
  DeformableParams deformable_params;
  deformable_params.damping = 0.2;
  std::vector<std::unique_ptr<SoftBody>> bodies;
  bodies.push_back(make_bullet_softbody(box, kLiver, damped));
  bodies.push_back(make_bullet_deformable(box, kLiver, deformable_params));
  for (const auto& body : bodies) {
    ASSERT_TRUE(run_to_rest(*body, input, kBulletDt, 1200)) << body->name();
    const Eigen::Vector3d total = body->constraint_forces().rowwise().sum();
    // An estimate from the last step's momentum balance: at rest, within the rest speed's
    // change per step.
    EXPECT_NEAR(total.z(), weight, 0.01 * weight) << body->name();
    EXPECT_LT(total.head<2>().norm(), 0.01 * weight) << body->name();
  }
}

// ---------------------------------------------------------------------------------------------
// Motion: the zero-motion trap, instability as a result

TEST(Bullet, FreeFallGainsGravityTimesDtInOneStep) {
  // Guards the trap of Bullet 3.24's implicit scheme without projection: zero motion.
  const TetMesh& box = small_box();
  std::vector<std::unique_ptr<SoftBody>> bodies = both_models(box, kLiver);
  for (const auto force :
       {DeformableParams::Force::kNeoHookean, DeformableParams::Force::kMassSpring,
        DeformableParams::Force::kCorotated}) {
    for (const bool implicit : {true, false}) {
      bodies.push_back(make_bullet_deformable(box, kLiver, deformable(force, implicit)));
    }
  }
  for (const auto& body : bodies) {
    StepInput input;  // gravity, nothing held
    ASSERT_TRUE(body->step(kBulletDt, input).finite);
    const Eigen::Vector3d mean_velocity = body->velocities().rowwise().mean();
    // The implicit scheme solves for the whole dv from zero, to the CG tolerance (cg_tolerance
    // 1e-8 on r.z: ~1e-4 relative; measured 1.7e-5).
    constexpr double kCgAccuracy = 1e-4;
    EXPECT_TRUE(mean_velocity.isApprox(input.gravity * kBulletDt, kCgAccuracy))
        << body->name() << " " << body->parameters().dump() << ": " << mean_velocity.transpose();
  }
}

/// Steps as the harness does, stopping at what the harness calls a blow-up (NaN, or faster than
/// a scene's default 50 m/s). Returns the step that blew up, or -1.
int first_unstable_step(SoftBody& body, const StepInput& input, double dt, int steps) {
  constexpr double kHarnessSpeedLimit = 50.0;  // m/s, scenes' default limits.max_speed
  for (int step = 0; step < steps; ++step) {
    const StepStats stats = body.step(dt, input);
    if (!stats.finite || !body.positions().allFinite()
        || body.velocities().colwise().norm().maxCoeff() > kHarnessSpeedLimit) {
      return step;
    }
  }
  return -1;
}

TEST(BulletDeformable, CorotatedIsExplicitOnlyUnstableAtOneSixtiethAndStableAtOneMillisecond) {
  const TetMesh& box = small_box();
  const std::vector<PositionConstraint> pins = pin_min_x_face(box);
  StepInput input;
  input.constraints = pins;
  const DeformableParams corotated = deformable(DeformableParams::Force::kCorotated, false);
  auto at_scene_dt = make_bullet_deformable(box, kLiver, corotated);
  const int blew_up = first_unstable_step(*at_scene_dt, input, kBulletDt, 60);
  EXPECT_GE(blew_up, 0) << "expected the explicit corotated force to blow up at 1/60 s";
  // Once reported, the body is left alone: the next step says so without calling Bullet.
  if (!at_scene_dt->positions().allFinite()) {
    EXPECT_FALSE(at_scene_dt->step(kBulletDt, input).finite);
  }
  auto small_step = make_bullet_deformable(box, kLiver, corotated);
  EXPECT_EQ(first_unstable_step(*small_step, input, 1e-3, 1000), -1);
}

// ---------------------------------------------------------------------------------------------
// Solver counters, energy, parameters

TEST(BulletDeformable, ReportsConjugateGradientIterationsUpToTheCap) {
  const std::vector<PositionConstraint> pins = pin_min_x_face(small_box());
  StepInput input;
  input.constraints = pins;
  DeformableParams capped;
  capped.cg_tolerance = 1e-300;  // never met: every solve runs to the cap
  capped.cg_max_iterations = 7;
  capped.newton_iterations = 2;
  auto body = make_bullet_deformable(small_box(), kLiver, capped);
  for (int step = 0; step < 3; ++step) {
    const StepStats stats = body->step(kBulletDt, input);
    EXPECT_EQ(stats.linear_solves, 2);
    EXPECT_EQ(stats.iterations, 2 * 7);
  }
  auto converging = make_bullet_deformable(small_box(), kLiver, DeformableParams{});
  const StepStats stats = converging->step(kBulletDt, input);
  EXPECT_EQ(stats.linear_solves, 1);
  EXPECT_GT(stats.iterations, 0);
  EXPECT_LT(stats.iterations, 300);
}

TEST(BulletDeformable, ElasticEnergyIsZeroAtRestAndGrowsWithTheSag) {
  const std::vector<PositionConstraint> pins = pin_min_x_face(small_box());
  StepInput input;
  input.constraints = pins;
  for (const auto force :
       {DeformableParams::Force::kNeoHookean, DeformableParams::Force::kMassSpring,
        DeformableParams::Force::kCorotated}) {
    auto body = make_bullet_deformable(small_box(), kLiver, deformable(force, true));
    // Round-off squared (measured 4e-32 J): the energy is evaluated free of cancellation.
    constexpr double kRestEnergy = 1e-28;  // J
    EXPECT_LT(std::abs(body->elastic_energy()), kRestEnergy);
    for (int step = 0; step < 10; ++step) {
      body->step(kBulletDt, input);
    }
    EXPECT_GT(body->elastic_energy(), 1e-6) << body->parameters().dump();
  }
  EXPECT_TRUE(std::isnan(make_bullet_softbody(small_box(), kLiver, {})->elastic_energy()));
}

TEST(BulletSoftBody, EchoesItsCalibrationRecord) {
  const nlohmann::json block = {
      {"stiffness", 0.25},
      {"calibrated", {{"against", "corotational_fem"}, {"dt", kBulletDt}, {"sag", 0.031}}}};
  const auto body = builtin_models().at("bullet_softbody").create(small_box(), kLiver, block, {});
  EXPECT_EQ(body->parameters()["stiffness"], 0.25);
  EXPECT_EQ(body->parameters()["calibrated"], block["calibrated"]);
  EXPECT_TRUE(builtin_models()
                  .at("bullet_softbody")
                  .create(small_box(), kLiver, nullptr, {})
                  ->parameters()["calibrated"]
                  .is_null());
}

TEST(Bullet, RejectsBadParametersNamingTheirKey) {
  const ParamSource source{"scene.json", "/models/bullet_softbody"};
  const auto create = [&](const std::string& model, const nlohmann::json& block) {
    builtin_models().at(model).create(small_box(), kLiver, block, source);
  };
  EXPECT_THAT(
      [&] {
        create("bullet_softbody", {{"stiffness", 1.5}});
      },
      ::testing::ThrowsMessage<InputError>(HasSubstr("/models/bullet_softbody/stiffness")));
  EXPECT_THAT(
      [&] {
        create("bullet_softbody", {{"calibrated", {{"against", "x"}, {"dt", 0.01}}}});
      },
      ::testing::ThrowsMessage<InputError>(HasSubstr("calibrated/sag")));
  EXPECT_THAT(
      [&] {
        create("bullet_softbody", {{"calibrated", 3}});
      },
      ::testing::ThrowsMessage<InputError>(HasSubstr("calibrated")));
  EXPECT_THAT(
      [&] {
        create("bullet_deformable", {{"force", "stvk"}});
      },
      ::testing::ThrowsMessage<InputError>(HasSubstr("force")));
}

}  // namespace
}  // namespace softbench
