// SPDX-License-Identifier: MIT
#include "harness/run/runner.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "harness/interrupt.h"
#include "harness/report/model_run_json.h"
#include "harness/report/run_report.h"
#include "models/json_file.h"
#include "models/json_reader.h"
#include "models/model_registry.h"
#include "scenes/scene.h"
#include "tests/harness/bar_sag_scene.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

namespace softbench::harness {
namespace {

// The bar of bar_sag_scene.h.
class RunnerTest : public ::testing::Test {
 protected:
  scenes::Scene scene(const std::string& models_block,
                      double dt = 1.0 / 60.0,
                      double duration = 3.0) const {
    return test_scenes::bar_sag(dir_, models_block, dt, duration);
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
  EXPECT_TRUE(run.stability.stable) << run.stability.divergence;
  EXPECT_EQ(run.timing.steps_run, run.timing.steps_planned);
  EXPECT_GT(run.timing.steps_per_second, 0.0);
  EXPECT_LE(run.timing.step_ms.median, run.timing.step_ms.p95);
  EXPECT_LE(run.timing.step_ms.p95, run.timing.step_ms.max);
  EXPECT_TRUE(run.recovery.measured);
  // Released at 0.5 s with 2.5 s to go: a damped elastic bar comes back to rest.
  EXPECT_LT(run.recovery.residual, 0.01);
  EXPECT_TRUE(run.recovery.time_to_one_percent.has_value());
  EXPECT_EQ(run.params["damping"], 0.5);
}

TEST_F(RunnerTest, ReportsABlowUpAsUnstableAndGoesOn) {
  RunOptions options;
  options.models = {"mass_spring"};
  // Symplectic Euler at dt = 1/30 with the thesis's damping is far beyond its stability limit.
  const std::vector<ModelRun> runs =
      run_scene(scene(
                    R"({"mass_spring": {"integrator": "symplectic_euler", "stiffness_from": "given",
                              "stiffness": 180, "damping": 5}})",
                    1.0 / 30.0),
                options);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_FALSE(runs[0].stability.stable);
  ASSERT_TRUE(runs[0].stability.diverged_at_step.has_value());
  EXPECT_LT(*runs[0].stability.diverged_at_step, runs[0].timing.steps_planned);
  EXPECT_FALSE(runs[0].stability.divergence.empty());
  EXPECT_FALSE(runs[0].recovery.measured);
  const nlohmann::json json = to_json(runs[0]);
  EXPECT_EQ(json["stability"]["stable"], false);
  EXPECT_EQ(json["stability"]["diverged_at_step"], *runs[0].stability.diverged_at_step);
}

TEST_F(RunnerTest, RejectsAnUnknownModelAndABadParameterBlockNamingTheScene) {
  RunOptions options;
  options.models = {"mass_spring"};
  const scenes::Scene unknown = scene(R"({"no_such_model": {}})");
  try {
    run_scene(unknown, options);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    // The registry's own message (its list of models depends on the build), after the pointer.
    std::string registry_message;
    try {
      builtin_models().at("no_such_model");
    } catch (const InputError& registry_error) {
      registry_message = registry_error.what();
    }
    EXPECT_EQ(std::string(error.what()),
              unknown.source.string() + ": /models/no_such_model: " + registry_message);
  }
  const scenes::Scene negative = scene(R"({"mass_spring": {"stiffness": -1}})");
  try {
    run_scene(negative, options);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              negative.source.string() + ": /models/mass_spring/stiffness: expected a number > 0, "
                                         "got -1");
  }
}

// The block of a model that is not run is read too, before anything runs: a typo there is not
// found only when that model's turn comes (or never).
TEST_F(RunnerTest, RejectsABadBlockOfAModelNotRunBeforeAnyModelRuns) {
  RunOptions options;
  options.models = {"mass_spring"};
  std::ostringstream progress;
  options.progress = &progress;
  try {
    run_scene(scene(R"({"corotational_fem": {"cg_tolerence": 1e-3}})"), options);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              dir_.path().string()
                  + "/bar_sag.json: /models/corotational_fem/cg_tolerence: unknown key (known "
                    "here: cg_max_iterations, cg_tolerance, coarse_vertices, formulation, preconditioner, "
                    "projected_warm_start, rayleigh_mass, rayleigh_stiffness, "
                    "refresh_iterations, rotation, rotation_iterations, rotation_tolerance, "
                    "solver, sweep_precision)");
  }
  EXPECT_EQ(progress.str(), "");  // mass_spring never ran
}

// A stop asked for (Ctrl-C, SIGTERM) ends the run between two steps with Interrupted.
TEST_F(RunnerTest, StopsBetweenStepsWhenAStopIsAskedFor) {
  RunOptions options;
  options.models = {"corotational_fem"};
  request_interrupt();
  EXPECT_THROW(run_scene(scene("{}"), options), Interrupted);
  clear_interrupt();
  EXPECT_TRUE(run_scene(scene("{}"), options).front().stability.stable);
}

// softbench run keeps what was measured up to the stop: the model's run ends after the step
// it was in, marked interrupted, and the models after it do not run.
TEST_F(RunnerTest, KeepsAnInterruptedRunMarkedAndRunsNoFurtherModel) {
  RunOptions options;
  options.models = {"corotational_fem", "mass_spring"};
  options.keep_interrupted = true;
  request_interrupt();
  const std::vector<ModelRun> runs = run_scene(scene("{}"), options);
  clear_interrupt();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].model, "corotational_fem");
  EXPECT_TRUE(runs[0].timing.interrupted);
  EXPECT_EQ(runs[0].timing.steps_run, 1);
  EXPECT_EQ(runs[0].samples.size(), 1u);
  EXPECT_TRUE(runs[0].stability.stable);
  const nlohmann::json json = to_json(runs[0]);
  EXPECT_EQ(json["timing"]["interrupted"], true);
  EXPECT_TRUE(model_run_from_json(JsonReader(json, "metrics.json", "")).timing.interrupted);
}

// A long run's per-step series stay bounded (memory and metrics.json): every step up to
// kSeriesCapacity, then an even thinning that still spans the whole run and keeps the peaks.
TEST_F(RunnerTest, ALongRunsSeriesStayBoundedAndSpanTheRun) {
  RunOptions options;
  options.models = {"mass_spring"};
  const double dt = 1.0 / 1000.0;
  const double duration = 70.0;  // 70,000 steps (past kSeriesCapacity) on a 30-tet bar: 2 s
  const scenes::Scene bar = scene("{}", dt, duration);
  const ModelRun run = run_scene(bar, options).front();
  ASSERT_EQ(run.timing.steps_run, 70000);
  EXPECT_LE(run.samples.size(), kSeriesCapacity);
  EXPECT_GE(run.samples.size(), kSeriesCapacity / 2);
  EXPECT_NEAR(run.samples.front().time, dt, 4 * dt);
  EXPECT_NEAR(run.samples.back().time, duration, 4 * dt);
  for (std::size_t i = 1; i < run.samples.size(); ++i) {
    ASSERT_GT(run.samples[i].time, run.samples[i - 1].time);
    ASSERT_LE(run.samples[i].time - run.samples[i - 1].time, 4.5 * dt);  // stride 2, a peak apart
  }
  EXPECT_GT(run.timing.steps_per_second, 0.0);
  EXPECT_LE(run.timing.step_ms.median, run.timing.step_ms.max);
}

TEST_F(RunnerTest, WritesMetricsWithEveryDocumentedField) {
  RunOptions options;
  options.models = {"mass_spring"};
  options.frames_every = 60;
  options.frames_dir = dir_.path() / "out" / "frames";
  const scenes::Scene bar = scene("{}");
  const std::vector<ModelRun> runs = run_scene(bar, options);
  write_reports(dir_.path() / "out", bar, runs);
  const nlohmann::json metrics = read_json_file((dir_.path() / "out" / "metrics.json").string());
  ASSERT_EQ(metrics["runs"].size(), 1u);
  const nlohmann::json& run = metrics["runs"][0];
  for (const char* key : {"model", "params", "mesh", "timing", "stability", "shape", "recovery",
                          "contact", "solver", "accuracy", "warnings", "series"}) {
    EXPECT_TRUE(run.contains(key)) << key;
  }
  for (const char* key : {"steps_planned", "steps_run", "step_ms", "steps_per_second",
                          "step_with_collision_ms", "steps_per_second_with_collision"}) {
    EXPECT_TRUE(run["timing"].contains(key)) << key;
  }
  for (const char* key : {"stable", "diverged_at_step", "divergence", "max_speed"}) {
    EXPECT_TRUE(run["stability"].contains(key)) << key;
  }
  EXPECT_TRUE(run["shape"].contains("max_inverted_tets"));
  EXPECT_TRUE(run["shape"].contains("volume_change"));
  EXPECT_TRUE(run["shape"].contains("final_inverted_tets"));
  EXPECT_TRUE(run["contact"].contains("loaded_travel"));
  EXPECT_TRUE(run["warnings"].is_array());
  EXPECT_TRUE(run["recovery"].contains("residual"));
  EXPECT_TRUE(run["recovery"].contains("time_to_one_percent_s"));
  EXPECT_TRUE(metrics["scene"].contains("material"));
  for (const char* key : {"version", "revision", "build_type", "compiler", "cpu", "threads"}) {
    EXPECT_TRUE(metrics["provenance"].contains(key)) << key;
  }
  EXPECT_TRUE(std::filesystem::exists(dir_.path() / "out" / "summary.md"));
  EXPECT_TRUE(
      std::filesystem::exists(dir_.path() / "out" / "frames" / "mass_spring" / "frame_00060.vtu"));
  EXPECT_EQ(read_vtu(dir_.path() / "out" / "frames" / "mass_spring" / "frame_00000.vtu")
                .tetrahedra.cols(),
            30);
}

}  // namespace
}  // namespace softbench::harness
