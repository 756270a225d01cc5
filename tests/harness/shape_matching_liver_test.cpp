// SPDX-License-Identifier: MIT
// Shape matching on the shipped liver scenes with the thesis's alpha and beta (their blocks),
// through the runner: held by its ligament band it hangs like tissue (its volume kept within
// 15%), takes the probe without crumpling, and comes back to its shape once the load is gone.
#include "harness/run/plausibility.h"
#include "harness/run/runner.h"
#include "scenes/scene.h"
#include "scenes/shipped_data.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace softbench::harness {
namespace {

ModelRun run_shipped(const std::string& scene_file) {
  // The scenes sit beside the shipped data folder.
  const scenes::Scene scene =
      scenes::load_scene(scenes::shipped_data_dir().parent_path() / scene_file);
  RunOptions options;
  options.models = {"shape_matching"};
  std::vector<ModelRun> runs = run_scene(scene, options);
  EXPECT_EQ(runs.size(), 1u);
  return runs.front();
}

TEST(ShapeMatchingLiver, HangsFromItsBandWithItsVolumeAndRecoversWhenGravityIsOff) {
  // Measured: 8.9% at most (59% with one pass a step, 144% with one pass and no volume kept),
  // 0.35% off its shape 2 s after gravity is off.
  const ModelRun run = run_shipped("liver_gravity.json");
  ASSERT_TRUE(run.stability.stable) << run.stability.divergence;
  EXPECT_LT(run.shape.volume_change, 0.15);
  ASSERT_TRUE(run.recovery.measured);
  EXPECT_LT(run.recovery.residual, 0.01);
}

TEST(ShapeMatchingLiver, TakesTheProbeAndLetsItGo) {
  // Measured: volume within 8.9% (the sag), 120 intersecting pairs and 0.65 N at the deepest,
  // the probe not inside the tissue once its contact settles (1.78 mm inside when a step had
  // only 4 contact passes), 0.30% off its shape 1.5 s after the withdrawal, no force once the
  // probe has gone. When a contact's corners anchored their clusters (as a
  // pin does) the liver crumpled under the probe: 178% volume change, 2,061 tets inverted,
  // 5.9 mm inside it, 120 N on the withdrawn probe.
  const ModelRun run = run_shipped("liver_press.json");
  ASSERT_TRUE(run.stability.stable) << run.stability.divergence;
  EXPECT_LT(run.shape.volume_change, 0.15);
  EXPECT_GT(run.contact.peak_tool_force, 0.0);
  EXPECT_GT(run.contact.max_triangle_pairs, 0);
  EXPECT_LT(run.contact.max_penetration_pressing, 0.001);
  ASSERT_TRUE(run.recovery.measured);
  EXPECT_LT(run.recovery.residual, 0.01);
  for (const Warning& warning : run.warnings) {
    EXPECT_NE(warning.id, kWarningForceAfterWithdrawal) << warning.message;
    EXPECT_NE(warning.id, kWarningInvertedTets) << warning.message;
  }
}

TEST(ShapeMatchingLiver, RecoversAfterTheGraspIsReleased) {
  // Measured: 0.04% off its shape 2 s after the release (30% with one pass a step).
  const ModelRun run = run_shipped("liver_pull.json");
  ASSERT_TRUE(run.stability.stable) << run.stability.divergence;
  ASSERT_TRUE(run.recovery.measured);
  EXPECT_LT(run.recovery.residual, 0.02);
  EXPECT_GT(run.contact.peak_tool_force, 0.0);
}

}  // namespace
}  // namespace softbench::harness
