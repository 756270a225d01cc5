// SPDX-License-Identifier: MIT
// What every registered model promises through the SoftBody interface, checked on each one with
// its default parameters: adding a model to builtin_models() adds it here.
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "models/model_registry.h"
#include "models/soft_body.h"
#include "tests/model_test_support.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace softbench {
namespace {

using test::pin_min_x_face;

/// A 12 x 8 x 8 cm box of 3 x 2 x 2 cells: small, but with interior and boundary vertices.
const TetMesh& small_box() {
  static const TetMesh mesh = make_tet_mesh(test::box_tets(3, 2, 2, 0.12, 0.08, 0.08));
  return mesh;
}

/// The liver material of the scenes.
const Material kMaterial{3000.0, 0.3, 1060.0};

/// 60 Hz, the scenes' step.
constexpr double kDt = 1.0 / 60.0;

/// Positions are O(0.1 m) and a few dozen flops deep: this is round-off.
constexpr double kPositionRoundoff = 1e-14;

class SoftBodyContract : public ::testing::TestWithParam<std::string> {
 public:
  std::unique_ptr<SoftBody> create(const nlohmann::json& params = nullptr) const {
    return builtin_models().at(GetParam()).create(small_box(), kMaterial, params, ParamSource{});
  }

 protected:
  /// The model's settling damping (its registry entry): quicker to rest, same equilibrium.
  nlohmann::json with_settling_damping() const {
    return builtin_models().at(GetParam()).settling_damping;
  }
  /// The damping the registry entry names, off.
  nlohmann::json undamped() const {
    nlohmann::json params = nlohmann::json::object();
    for (const auto& [key, value] : builtin_models().at(GetParam()).settling_damping.items()) {
      params[key] = 0.0;
    }
    return params;
  }
  static const Eigen::VectorXd& masses() {
    static const Eigen::VectorXd lumped = lumped_masses(small_box(), kMaterial.density);
    return lumped;
  }
};

TEST_P(SoftBodyContract, NameIsTheRegistryKey) {
  EXPECT_EQ(create()->name(), GetParam());
}

TEST_P(SoftBodyContract, StartsAtRestOnTheMesh) {
  const auto body = create();
  EXPECT_EQ(body->positions(), small_box().rest_positions());
  EXPECT_TRUE(body->velocities().isZero(0.0));
  EXPECT_EQ(body->velocities().cols(), small_box().num_vertices());
}

TEST_P(SoftBodyContract, RestStaysAtRestWithoutGravityOrConstraints) {
  const auto body = create();
  StepInput input;
  input.gravity.setZero();
  for (int step = 0; step < 20; ++step) {
    ASSERT_TRUE(body->step(kDt, input).finite);
  }
  EXPECT_TRUE(body->positions().isApprox(small_box().rest_positions(), kPositionRoundoff));
  EXPECT_LT(body->velocities().cwiseAbs().maxCoeff(), kPositionRoundoff / kDt);
}

TEST_P(SoftBodyContract, ResetRestoresTheRestStateExactly) {
  const auto body = create();
  const std::vector<PositionConstraint> pins = pin_min_x_face(small_box());
  StepInput input;
  input.constraints = pins;
  for (int step = 0; step < 10; ++step) {
    body->step(kDt, input);
  }
  ASSERT_NE(body->positions(), small_box().rest_positions());
  body->reset();
  EXPECT_EQ(body->positions(), small_box().rest_positions());
  EXPECT_TRUE(body->velocities().isZero(0.0));
}

TEST_P(SoftBodyContract, SetVelocitiesReplacesTheVelocitiesAndKeepsThePositions) {
  const auto body = create();
  Eigen::Matrix3Xd velocities(3, small_box().num_vertices());
  for (Eigen::Index v = 0; v < velocities.cols(); ++v) {
    velocities.col(v) =
        Eigen::Vector3d(0.1, -0.2, 0.3) + 0.01 * static_cast<double>(v) * Eigen::Vector3d::UnitX();
  }
  body->set_velocities(velocities);
  EXPECT_EQ(body->velocities(), velocities);
  EXPECT_EQ(body->positions(), small_box().rest_positions());
  EXPECT_THROW(body->set_velocities(Eigen::Matrix3Xd::Zero(3, 2)), std::invalid_argument);
  velocities(1, 4) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(body->set_velocities(velocities), std::invalid_argument);
  body->reset();
  EXPECT_TRUE(body->velocities().isZero(0.0));
}

/// bullet_softbody's world hands dt to the body as a float (bullet_soft_body.h): a step moves a
/// node by v float(dt), 2^-24 relative off v dt.
double time_step_rounding(const std::string& model) {
  return model == "bullet_softbody" ? 6e-8 : 0.0;
}

TEST_P(SoftBodyContract, ARigidTranslationVelocityMovesEveryVertexByVDt) {
  // Damping that brakes the body as a whole (mass damping, Bullet's kDP) off: what is left
  // conserves linear momentum, and a rigid translation stores no elastic force.
  for (const int steps : {1, 10}) {
    const auto body = create(undamped());
    const Eigen::Vector3d velocity(0.3, -0.2, 0.1);  // m/s
    body->set_velocities(velocity.replicate(1, small_box().num_vertices()));
    double constraint_error = 0.0;
    for (int step = 0; step < steps; ++step) {
      const StepStats stats = body->step(kDt, test::no_gravity());
      ASSERT_TRUE(stats.finite);
      constraint_error = std::max(constraint_error, stats.max_constraint_error);
    }
    const Eigen::Vector3d travel = steps * kDt * velocity;
    const double tolerance =
        kPositionRoundoff * steps + time_step_rounding(GetParam()) * travel.norm();
    const Eigen::Matrix3Xd expected = small_box().rest_positions().colwise() + travel;
    EXPECT_LE((body->positions() - expected).colwise().norm().maxCoeff(),
              tolerance + constraint_error)
        << "after " << steps << " step(s)";
    // And it keeps the velocity: off by no more than would move it by the tolerance.
    EXPECT_LE((body->velocities().colwise() - velocity).colwise().norm().maxCoeff(),
              tolerance / (steps * kDt))
        << "after " << steps << " step(s)";
  }
}

TEST_P(SoftBodyContract, PinnedVerticesStayWithinTheReportedConstraintError) {
  const auto body = create();
  const std::vector<PositionConstraint> pins = pin_min_x_face(small_box());
  StepInput input;
  input.constraints = pins;
  for (int step = 0; step < 30; ++step) {
    const StepStats stats = body->step(kDt, input);
    ASSERT_TRUE(stats.finite);
    for (const PositionConstraint& pin : pins) {
      ASSERT_LE((body->positions().col(pin.vertex) - pin.target).norm(),
                stats.max_constraint_error + kPositionRoundoff)
          << "vertex " << pin.vertex << " at step " << step;
    }
  }
}

TEST_P(SoftBodyContract, ConstraintsMovingAllVerticesRigidlyLeaveNoElasticEnergy) {
  const auto body = create();
  const Eigen::Affine3d motion = Eigen::Translation3d(0.01, -0.02, 0.005)
                                 * Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 1, 2).normalized());
  const Eigen::Matrix3Xd targets = motion * small_box().rest_positions();
  std::vector<PositionConstraint> pins;
  for (int v = 0; v < small_box().num_vertices(); ++v) {
    pins.push_back({v, targets.col(v), kExact});
  }
  StepInput input;
  input.gravity.setZero();
  input.constraints = pins;
  const StepStats stats = body->step(kDt, input);
  ASSERT_TRUE(stats.finite);
  for (const PositionConstraint& pin : pins) {
    EXPECT_LE((body->positions().col(pin.vertex) - pin.target).norm(),
              stats.max_constraint_error + kPositionRoundoff);
  }
  const double energy = body->elastic_energy();
  if (!std::isnan(energy)) {  // NaN: the model has no elastic energy (soft_body.h)
    // The energy of a uniform strain of 1e-9, far above round-off (~1e-15) and far below any
    // real deformation.
    const double volume = 0.12 * 0.08 * 0.08;
    EXPECT_LT(energy, 0.5 * kMaterial.young_modulus * 1e-18 * volume);
  }
}

TEST_P(SoftBodyContract, StaysFiniteUnderGravityWithOneFacePinned) {
  const auto body = create();
  const std::vector<PositionConstraint> pins = pin_min_x_face(small_box());
  StepInput input;
  input.constraints = pins;
  for (int step = 0; step < 100; ++step) {
    ASSERT_TRUE(body->step(kDt, input).finite) << "step " << step;
  }
  EXPECT_TRUE(body->positions().allFinite());
  EXPECT_TRUE(body->velocities().allFinite());
  // It hangs: the free end moved down.
  EXPECT_LT(body->positions().row(2).mean(), small_box().rest_positions().row(2).mean());
}

TEST_P(SoftBodyContract, ParametersRoundTripThroughTheFactory) {
  const nlohmann::json effective = create()->parameters();
  EXPECT_TRUE(effective.is_object());
  EXPECT_EQ(create(effective)->parameters(), effective);
  // Every documented parameter is echoed.
  for (const ParameterDoc& doc : builtin_models().at(GetParam()).parameters) {
    EXPECT_TRUE(effective.contains(doc.name)) << doc.name;
    EXPECT_EQ(effective[doc.name], doc.default_value) << doc.name;
  }
}

// --- determinism, balance, energy ---------------------------------------------------------------

/// Drives a fresh body through 30 steps of a load that exercises every code path of a step:
/// gravity, one face pinned, the opposite face pulled along by moving exact constraints.
Eigen::Matrix3Xd driven_positions(const SoftBodyContract& test, SoftBody& body) {
  (void)test;
  const TetMesh& mesh = small_box();
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const double max_x = rest.row(0).maxCoeff();
  std::vector<PositionConstraint> constraints = pin_min_x_face(mesh);
  const std::size_t pinned = constraints.size();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (rest(0, v) >= max_x - 1e-12) {
      constraints.push_back({v, rest.col(v), kExact});
    }
  }
  StepInput input;
  for (int step = 0; step < 30; ++step) {
    for (std::size_t c = pinned; c < constraints.size(); ++c) {
      constraints[c].target =
          rest.col(constraints[c].vertex) + Eigen::Vector3d(0.0005 * step, 0, 0);
    }
    input.constraints = constraints;
    EXPECT_TRUE(body.step(kDt, input).finite);
  }
  return body.positions();
}

TEST_P(SoftBodyContract, ARepeatedRunIsBitIdentical) {
  const auto first = create();
  const auto second = create();
  const Eigen::Matrix3Xd a = driven_positions(*this, *first);
  const Eigen::Matrix3Xd b = driven_positions(*this, *second);
  EXPECT_TRUE((a.array() == b.array()).all())
      << "largest difference " << (a - b).cwiseAbs().maxCoeff() << " m";
}

TEST_P(SoftBodyContract, OneAndTwoThreadsGiveBitIdenticalResults) {
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = create();
  const Eigen::Matrix3Xd a = driven_positions(*this, *one);
  omp_set_num_threads(2);
  const auto two = create();
  const Eigen::Matrix3Xd b = driven_positions(*this, *two);
  omp_set_num_threads(threads);
  EXPECT_TRUE((a.array() == b.array()).all())
      << "largest difference " << (a - b).cwiseAbs().maxCoeff() << " m";
}

TEST_P(SoftBodyContract, ReactionsBalanceTheWeightAtRest) {
  const auto body = create(with_settling_damping());
  const std::vector<PositionConstraint> pins = pin_min_x_face(small_box());
  StepInput input;
  input.constraints = pins;
  test::expect_reactions_balance_weight_at_rest(*body, masses(), input, pins);
}

TEST_P(SoftBodyContract, GainsNoEnergyInUndampedFreeMotion) {
  const auto body = create(undamped());
  if (std::isnan(body->elastic_energy())) {
    GTEST_SKIP() << GetParam() << " has no elastic energy to account for";
  }
  // Released from rest in a 10% stretch along x, no gravity, nothing held: it oscillates, and
  // the total energy may only fall (an integrator may dissipate, never create).
  Eigen::Matrix3Xd stretched = small_box().rest_positions();
  stretched.row(0) *= 1.1;
  test::place_at_rest(*body, stretched);
  const double initial = body->elastic_energy();
  ASSERT_GT(initial, 0.0);
  double largest = initial;
  for (int step = 0; step < 120; ++step) {  // 2 s
    ASSERT_TRUE(body->step(kDt, test::no_gravity()).finite) << "step " << step;
    largest = std::max(largest, body->elastic_energy() + test::kinetic_energy(*body, masses()));
  }
  constexpr double kGainTolerance = 1e-9;  // relative: round-off, not integration error
  EXPECT_LE(largest, initial * (1.0 + kGainTolerance))
      << "gained " << 100.0 * (largest / initial - 1.0) << "% of " << initial << " J";
}

/// Relative to the largest force. A wrong or missing term shows at O(1); what remains is the
/// central difference's truncation and, for corotational_fem's default warm-started quaternion
/// rotations (at most 3 iterations a step, 1e-6 rad), rotations not yet converged: 4e-5
/// measured on this state. mass_spring, neo_hookean and bullet_deformable pass at 1e-7, and so
/// does corotational_fem with its exact SVD rotations (checked in its own tests).
constexpr double kGradientTolerance = 1e-4;

TEST_P(SoftBodyContract, ForcesAreTheGradientOfTheElasticEnergy) {
  const auto body = create();
  if (std::isnan(body->elastic_energy())) {
    GTEST_SKIP() << GetParam() << " has no elastic energy to differentiate";
  }
  // A deformed state (a shear plus a twist): no symmetry hides a wrong term.
  Eigen::Matrix3Xd x = small_box().rest_positions();
  for (Eigen::Index v = 0; v < x.cols(); ++v) {
    const Eigen::Vector3d p = x.col(v);
    x.col(v) += Eigen::Vector3d(0.1 * p.y() + 0.05 * p.z(), 0.08 * p.x() * p.z() / 0.08,
                                -0.06 * p.x() + 0.04 * p.y());
  }
  test::expect_forces_match_energy_gradient(*body, x, kGradientTolerance);
}

TEST_P(SoftBodyContract, ReportsTheMemoryItHolds) {
  EXPECT_GT(create()->memory_bytes(), 0U);
}

INSTANTIATE_TEST_SUITE_P(AllModels,
                         SoftBodyContract,
                         ::testing::ValuesIn(builtin_models().names()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return param.param;
                         });

}  // namespace
}  // namespace softbench
