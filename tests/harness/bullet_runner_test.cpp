// SPDX-License-Identifier: MIT
// The Bullet baselines through the harness: a run Bullet cannot survive is a result (unstable,
// with the step it diverged at), not a crash; a stable one is measured like any model.
#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_validation.h"
#include "harness/report/model_run_json.h"
#include "harness/report/run_report.h"
#include "harness/run/runner.h"
#include "scenes/scene.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace softbench::harness {
namespace {

// A 10 x 4 x 4 cm bar of liver-like tissue clamped at x = 0, sagging under gravity for 1 s.
class BulletRunnerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    write_msh(dir_.path() / "bar.msh", test::box_tets(5, 2, 2, 0.1, 0.04, 0.04));
  }

  scenes::Scene scene(const std::string& models_block, double dt) const {
    const std::string text = R"({
      "name": "bullet_bar",
      "mesh": "bar.msh",
      "material": {"young_modulus": 3000, "poisson_ratio": 0.3, "density": 1060},
      "gravity": [0, 0, -9.81],
      "time": {"dt": )" + std::to_string(dt)
                             + R"(, "duration": 1.0},
      "fixed": {"box": {"min": [-0.001, -1, -1], "max": [0.001, 1, 1]}},
      "models": )" + models_block
                             + "}";
    return scenes::load_scene(dir_.write("bullet_bar.json", text));
  }

  test::TempDir dir_;
};

TEST_F(BulletRunnerTest, ExplicitCorotatedAtOneSixtiethIsReportedUnstableNotACrash) {
  RunOptions options;
  options.models = {"bullet_deformable", "bullet_softbody"};
  const std::vector<ModelRun> runs = run_scene(
      scene(R"({"bullet_deformable": {"force": "corotated", "implicit": false}})", 1.0 / 60.0),
      options);
  ASSERT_EQ(runs.size(), 2u);
  const ModelRun& corotated = runs[0];
  EXPECT_FALSE(corotated.stability.stable);
  ASSERT_TRUE(corotated.stability.diverged_at_step.has_value());
  EXPECT_LT(*corotated.stability.diverged_at_step, corotated.timing.steps_planned);
  EXPECT_FALSE(corotated.stability.divergence.empty());
  const nlohmann::json json = to_json(corotated);
  EXPECT_EQ(json["stability"]["stable"], false);
  EXPECT_EQ(json["params"]["force"], "corotated");
  // The run goes on with the next model.
  EXPECT_TRUE(runs[1].stability.stable) << runs[1].stability.divergence;
  EXPECT_EQ(runs[1].timing.steps_run, runs[1].timing.steps_planned);
}

TEST_F(BulletRunnerTest, ImplicitNeoHookeanAtOneSixtiethRunsStableWithExactPins) {
  RunOptions options;
  options.models = {"bullet_deformable"};
  const std::vector<ModelRun> runs = run_scene(scene("{}", 1.0 / 60.0), options);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_TRUE(runs[0].stability.stable) << runs[0].stability.divergence;
  EXPECT_EQ(runs[0].solver.max_constraint_error, 0.0);
  EXPECT_GT(runs[0].solver.mean_iterations, 0.0);  // CG iterations reach the metrics
  EXPECT_GT(runs[0].solver.linear_solves, 0);
}

}  // namespace
}  // namespace softbench::harness
