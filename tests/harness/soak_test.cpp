// SPDX-License-Identifier: MIT
// The soak: cycles of the scene's loading, the body carried on; memory, energy and shape drift
// per cycle, a blow-up reported and ending the soak.
#include "harness/soak/soak.h"

#include "geometry/input_error.h"
#include "harness/interrupt.h"
#include "harness/report/soak_report.h"
#include "scenes/scene.h"
#include "tests/harness/bar_sag_scene.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include <streambuf>
#include <string>

namespace softbench::harness {
namespace {

using ::testing::HasSubstr;

// The bar of bar_sag_scene.h in cycles of 1.5 s by default: it sags under gravity for 0.5 s
// and springs back with gravity off for the rest, a damped cycle that ends where it began.
class SoakTest : public ::testing::Test {
 protected:
  scenes::Scene scene(const std::string& models_block,
                      double dt = 1.0 / 60.0,
                      double duration = 1.5) const {
    return test_scenes::bar_sag(dir_, models_block, dt, duration);
  }
  test::TempDir dir_;
};

TEST_F(SoakTest, CyclesTheSceneAndComesBackToTheSameStateEachCycle) {
  const scenes::Scene bar =
      scene(R"({"corotational_fem": {"rayleigh_mass": 5.0}})");
  SoakOptions options;
  options.model = "corotational_fem";
  options.steps = 90 * 30 + 45;  // 30 whole cycles of 90 steps and half of one
  SoakReport report = run_soak(bar, read_scene_mesh(bar), options);
  EXPECT_TRUE(report.stable) << report.divergence;
  EXPECT_EQ(report.steps_run, options.steps);
  EXPECT_EQ(report.steps_per_cycle, 90);
  ASSERT_EQ(report.cycles.size(), 31u);
  EXPECT_EQ(report.cycles.back().steps, options.steps);
  // Each cycle ends recovered: the end states agree to well within 0.1% of the diagonal, and the
  // energy at the end of each whole cycle is the first's (damped, with gravity off, near zero).
  for (std::size_t i = 0; i + 1 < report.cycles.size(); ++i) {
    EXPECT_LT(report.cycles[i].shape_drift, 1e-3) << "cycle " << i + 1;
  }
  EXPECT_GT(report.cycles.front().resident_bytes, 0u);
  EXPECT_GE(report.peak_resident, report.resident_at_end);
  // Nothing a step allocates outlives it: once warm, the heap in use at the end of every cycle
  // stays within a few of the allocator's small blocks of the middle cycle's (the soak's own
  // series is reserved up front). The warm-up is the allocator's per-thread caches filling, a
  // few hundred bytes a cycle over the first several; the second half of the soak is far past
  // it. Run alone the heap is the same to the byte; under a loaded `ctest -j2` it was 32 to 144
  // bytes lower at some cycle ends than at the middle one, never higher. A leak of one block a
  // step would add 16 bytes or more a step: 1,440 a cycle.
  constexpr double kAllocatorJitter = 512.0;  // bytes
  EXPECT_GT(report.heap_at_half, 0u);
  const std::size_t half = report.cycles.size() / 2;
  for (std::size_t i = half; i < report.cycles.size(); ++i) {
    EXPECT_NEAR(static_cast<double>(report.cycles[i].heap_bytes),
                static_cast<double>(report.cycles[half].heap_bytes), kAllocatorJitter)
        << "cycle " << i + 1;
  }
  EXPECT_EQ(report.heap_at_half, report.cycles[half].heap_bytes);
  const double second_half_steps =
      static_cast<double>(report.cycles.back().steps - report.cycles[half].steps);
  EXPECT_LE(std::abs(report.heap_growth_per_step), kAllocatorJitter / second_half_steps);
  EXPECT_GT(report.speed_ratio, 0.0);
  const nlohmann::json json = soak_json(report);
  EXPECT_EQ(json["cycles"].size(), 31u);
  EXPECT_TRUE(json["summary"].contains("energy_drift"));
  EXPECT_THAT(soak_markdown(report), HasSubstr("resident memory after warm-up"));
  EXPECT_THAT(soak_markdown(report), HasSubstr("heap in use at the middle cycle's end / at the end"));
}

TEST_F(SoakTest, ReportsABlowUpAndStops) {
  // Symplectic Euler at dt = 1/30 with stiff thesis springs blows up within a few steps.
  const scenes::Scene bar = scene(
      R"({"mass_spring": {"integrator": "symplectic_euler", "stiffness_from": "given",
                          "stiffness": 180, "damping": 5}})",
      1.0 / 30.0);
  SoakOptions options;
  options.model = "mass_spring";
  options.steps = 100000;
  const SoakReport report = run_soak(bar, read_scene_mesh(bar), options);
  EXPECT_FALSE(report.stable);
  ASSERT_TRUE(report.diverged_at_step.has_value());
  EXPECT_LT(report.steps_run, options.steps);
  EXPECT_EQ(report.steps_run, *report.diverged_at_step + 1);
  EXPECT_THAT(soak_markdown(report), HasSubstr("UNSTABLE at step"));
}

// Ctrl-C during a long soak keeps what the whole cycles before it measured. The stop is asked
// for as the first cycle's progress line is written, so it lands in the second cycle.
TEST_F(SoakTest, AnInterruptedSoakKeepsItsWholeCycles) {
  struct RaisesTheFlag : std::streambuf {
    int overflow(int c) override {
      request_interrupt();
      return c;
    }
  } raises;
  std::ostream progress(&raises);
  const scenes::Scene bar = scene(R"({"corotational_fem": {"rayleigh_mass": 5.0}})");
  SoakOptions options;
  options.model = "corotational_fem";
  options.steps = 90 * 10;
  options.progress = &progress;
  options.live_progress = true;  // a line every cycle
  options.keep_interrupted = true;
  const SoakReport report = run_soak(bar, read_scene_mesh(bar), options);
  clear_interrupt();
  EXPECT_TRUE(report.interrupted);
  EXPECT_TRUE(report.stable);
  ASSERT_EQ(report.cycles.size(), 1u);
  EXPECT_EQ(report.cycles.front().steps, 90);
  EXPECT_EQ(report.steps_run, 91);  // the second cycle's first step, then the stop
  EXPECT_TRUE(soak_json(report)["interrupted"].get<bool>());
  EXPECT_THAT(soak_markdown(report), HasSubstr("interrupted"));
  // Without keep_interrupted the stop is an Interrupted, nothing returned.
  options.keep_interrupted = false;
  EXPECT_THROW(run_soak(bar, read_scene_mesh(bar), options), Interrupted);
  clear_interrupt();
}

TEST_F(SoakTest, KeepsABoundedNumberOfCycles) {
  // Cycles of two steps: 3,000 of them in 6,000 steps.
  const scenes::Scene bar = scene("{}", 1.0 / 60.0, 2.0 / 60.0);
  SoakOptions options;
  options.model = "mass_spring";
  options.steps = 2LL * 3000;
  const SoakReport report = run_soak(bar, read_scene_mesh(bar), options);
  EXPECT_TRUE(report.stable) << report.divergence;
  EXPECT_LE(report.cycles.size(), 1024u);
  EXPECT_GE(report.cycles.size(), 512u);
  EXPECT_EQ(report.cycles.front().cycle, 1);
  EXPECT_GT(report.cycles.back().cycle, 2900);
}

}  // namespace
}  // namespace softbench::harness
