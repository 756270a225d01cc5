// SPDX-License-Identifier: MIT
// What every registered model promises through the SoftBody interface, checked on each one with
// its default parameters: adding a model to builtin_models() adds it here.
#include "geometry/mesh_validation.h"
#include "models/model_registry.h"
#include "models/soft_body.h"
#include "tests/model_test_support.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
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
 protected:
  std::unique_ptr<SoftBody> create(const nlohmann::json& params = nullptr) const {
    return builtin_models().at(GetParam()).create(small_box(), kMaterial, params, ParamSource{});
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
