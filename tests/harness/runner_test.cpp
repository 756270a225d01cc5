// SPDX-License-Identifier: MIT
#include "harness/runner.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "harness/report.h"
#include "models/json_reader.h"
#include "scenes/scene.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softbench::harness {
namespace {

using ::testing::HasSubstr;

// A 10 x 2 x 2 cm bar clamped at x = 0, stiff enough (50 kPa) that edge springs alone bring it
// back (a softer one folds, which mass-spring cannot undo), sagging under gravity for 0.5 s, then
// released: gravity off.
class RunnerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    write_msh(dir_.path() / "bar.msh", test::box_tets(5, 1, 1, 0.1, 0.02, 0.02));
  }

  scenes::Scene scene(const std::string& models_block, double dt = 1.0 / 60.0) const {
    const std::string text = R"({
      "name": "bar_sag",
      "mesh": "bar.msh",
      "material": {"young_modulus": 50000, "poisson_ratio": 0.3, "density": 1000},
      "gravity": {"acceleration": [0, 0, -9.81], "off_at": 0.5},
      "time": {"dt": )" + std::to_string(dt)
                             + R"(, "duration": 3.0},
      "fixed": {"box": {"min": [-0.001, -1, -1], "max": [0.001, 1, 1]}},
      "models": )" + models_block
                             + "}";
    const auto path = dir_.write("bar_sag.json", text);
    return scenes::load_scene(path);
  }

  test::TempDir dir_;
};

TEST_F(RunnerTest, RunsAStableModelAndMeasuresItsRecovery) {
  RunOptions options;
  options.models = {"mass_spring"};
  const std::vector<ModelRun> runs = run_scene(
      scene(R"({"mass_spring": {"stiffness_from": "young_modulus", "damping": 0.5}})"), options);
  ASSERT_EQ(runs.size(), 1u);
  const ModelRun& run = runs[0];
  EXPECT_TRUE(run.stable) << run.divergence;
  EXPECT_EQ(run.steps_run, run.steps_planned);
  EXPECT_GT(run.fps, 0.0);
  EXPECT_LE(run.step_ms.median, run.step_ms.p95);
  EXPECT_LE(run.step_ms.p95, run.step_ms.max);
  EXPECT_TRUE(run.recovery_measured);
  // Released at 0.5 s with 2.5 s to go: a damped elastic bar comes back to rest.
  EXPECT_LT(run.recovery_residual, 0.01);
  EXPECT_TRUE(run.time_to_1pct.has_value());
  EXPECT_EQ(run.params["damping"], 0.5);
}

TEST_F(RunnerTest, ReportsABlowUpAsUnstableAndGoesOn) {
  RunOptions options;
  options.models = {"mass_spring"};
  // Symplectic Euler at dt = 1/30 with the thesis's damping is far beyond its stability limit.
  const std::vector<ModelRun> runs = run_scene(
      scene(
          R"({"mass_spring": {"integrator": "symplectic_euler", "stiffness": 180, "damping": 5}})",
          1.0 / 30.0),
      options);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_FALSE(runs[0].stable);
  ASSERT_TRUE(runs[0].diverged_at_step.has_value());
  EXPECT_LT(*runs[0].diverged_at_step, runs[0].steps_planned);
  EXPECT_FALSE(runs[0].divergence.empty());
  EXPECT_FALSE(runs[0].recovery_measured);
  const nlohmann::json json = to_json(runs[0]);
  EXPECT_EQ(json["stable"], false);
  EXPECT_EQ(json["diverged_at_step"], *runs[0].diverged_at_step);
}

TEST_F(RunnerTest, RejectsAnUnknownModelAndABadParameterBlockNamingTheScene) {
  RunOptions options;
  options.models = {"mass_spring"};
  try {
    run_scene(scene(R"({"no_such_model": {}})"), options);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("bar_sag.json: /models/no_such_model"));
  }
  try {
    run_scene(scene(R"({"mass_spring": {"stiffness": -1}})"), options);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("bar_sag.json: /models/mass_spring/stiffness"));
  }
}

TEST_F(RunnerTest, WritesMetricsWithEveryDocumentedField) {
  RunOptions options;
  options.models = {"mass_spring"};
  options.frames_every = 60;
  options.frames_dir = dir_.path() / "out" / "frames";
  const scenes::Scene bar = scene("{}");
  const std::vector<ModelRun> runs = run_scene(bar, options);
  write_reports(dir_.path() / "out", bar, runs);
  const nlohmann::json metrics = parse_json_file((dir_.path() / "out" / "metrics.json").string());
  ASSERT_EQ(metrics["runs"].size(), 1u);
  const nlohmann::json& run = metrics["runs"][0];
  for (const char* key :
       {"model", "params", "mesh", "steps", "step_ms", "fps", "fps_with_collision", "stable",
        "max_inverted_tets", "volume_change", "recovery", "accuracy"}) {
    EXPECT_TRUE(run.contains(key)) << key;
  }
  EXPECT_TRUE(run["recovery"].contains("residual_rms_rel"));
  EXPECT_TRUE(run["recovery"].contains("time_to_1pct_s"));
  EXPECT_TRUE(metrics["scene"].contains("material"));
  EXPECT_TRUE(std::filesystem::exists(dir_.path() / "out" / "summary.md"));
  EXPECT_TRUE(
      std::filesystem::exists(dir_.path() / "out" / "frames" / "mass_spring" / "frame_00060.vtu"));
  EXPECT_EQ(read_vtu(dir_.path() / "out" / "frames" / "mass_spring" / "frame_00000.vtu")
                .tetrahedra.cols(),
            30);
}

}  // namespace
}  // namespace softbench::harness
