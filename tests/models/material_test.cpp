// SPDX-License-Identifier: MIT
#include "models/material.h"

#include "geometry/input_error.h"
#include "tests/test_tolerances.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

namespace softbench {
namespace {

using ::testing::HasSubstr;

std::string rejection_message(const Material& material) {
  try {
    validate_material(material, "scene.json: /material");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(Material, LameParametersReproduceYoungsModulusAndPoissonsRatio) {
  const Material material{5000.0, 0.45, 1060.0};
  const LameParameters lame = lame_parameters(material);
  // Inverse relations: E = mu (3 lambda + 2 mu) / (lambda + mu), nu = lambda / (2 (lambda + mu)).
  const double young = lame.mu * (3 * lame.lambda + 2 * lame.mu) / (lame.lambda + lame.mu);
  const double poisson = lame.lambda / (2 * (lame.lambda + lame.mu));
  EXPECT_NEAR(young, 5000.0, 5000.0 * test::kRoundoff);
  EXPECT_NEAR(poisson, 0.45, test::kRoundoff);
}

TEST(Material, RejectsPoissonRatioAtOneHalf) {
  EXPECT_THAT(
      rejection_message({3000.0, 0.5, 1000.0}),
      HasSubstr("scene.json: /material/poisson_ratio: expected a number in [0, 0.5), got 0.5"));
}

TEST(Material, RejectsNegativeStiffnessDensityAndNaN) {
  EXPECT_THAT(rejection_message({-1.0, 0.3, 1000.0}), HasSubstr("/young_modulus"));
  EXPECT_THAT(rejection_message({3000.0, 0.3, 0.0}), HasSubstr("/density"));
  EXPECT_THAT(rejection_message({std::numeric_limits<double>::quiet_NaN(), 0.3, 1000.0}),
              HasSubstr("got nan"));
}

TEST(Material, AcceptsTheThesisAndTissueParameters) {
  EXPECT_EQ(rejection_message({3000.0, 0.3, 1000.0}), "");
  EXPECT_EQ(rejection_message({5000.0, 0.45, 1060.0}), "");
}

}  // namespace
}  // namespace softbench
