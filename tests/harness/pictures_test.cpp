// SPDX-License-Identifier: MIT
// The pictures `softbench snapshot` and compare.md show, on the shipped liver_press scene with
// corotational_fem: the settled liver drawn where its vertices project, and the press changing
// the picture around the probe's tip and the probe's shaft, not across the rest of the liver.
#include "harness/report/pictures.h"
#include "harness/run/runner.h"
#include "render/image.h"
#include "scenes/instrument_path.h"
#include "scenes/scene.h"
#include "scenes/shipped_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace softbench::harness {
namespace {

constexpr int kWidth = 240;
constexpr int kHeight = 180;

/// A tissue pixel: the tissue colour lit, red well above green and blue (the grey probe and
/// the grey ground are not).
bool is_tissue(const std::uint8_t* p) { return p[0] > p[1] + 30 && p[0] > p[2] + 30; }

TEST(Pictures, TheLiverIsDrawnWhereItIsAndThePressChangesOnlyWhereTheProbeIs) {
  const scenes::Scene scene =
      scenes::load_scene(scenes::shipped_data_dir().parent_path() / "liver_press.json");
  const SceneMesh mesh = read_scene_mesh(scene);
  // Settled under gravity with the probe still above it (it starts down at 1.5 s), and at the
  // deepest press (2.5 s: 2 cm past first contact).
  RunOptions options;
  options.models = {"corotational_fem"};
  options.picture_times = {1.45, 2.5};
  const std::vector<ModelRun> runs = run_scene(scene, mesh, options);
  ASSERT_EQ(runs.size(), 1U);
  ASSERT_EQ(runs[0].pictures.size(), 2U);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "softbench_pictures_test.png";
  write_pictures(path, scene, mesh, runs, 2, kWidth, kHeight);
  const render::Image image = render::read_png(path);
  std::filesystem::remove(path);
  ASSERT_EQ(image.width, 2 * kWidth + 4);
  ASSERT_EQ(image.height, kHeight);

  // The settled liver's tissue pixels span where its vertices project (within 2 pixels: the
  // silhouette's anti-aliased edge).
  const render::Camera camera = pictures_camera(mesh, static_cast<double>(kWidth) / kHeight);
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (int v = 0; v < mesh.body.num_vertices(); ++v) {
    const Eigen::Vector2d p = camera.pixel_of(runs[0].pictures[0].positions.col(v), kWidth, kHeight);
    x0 = std::min(x0, p.x());
    x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y());
    y1 = std::max(y1, p.y());
  }
  double tx0 = 1e9, tx1 = -1e9, ty0 = 1e9, ty1 = -1e9;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (is_tissue(image.pixel(x, y))) {
        tx0 = std::min(tx0, x + 0.5);
        tx1 = std::max(tx1, x + 0.5);
        ty0 = std::min(ty0, y + 0.5);
        ty1 = std::max(ty1, y + 0.5);
      }
    }
  }
  EXPECT_NEAR(tx0, x0, 2.0);
  EXPECT_NEAR(tx1, x1, 2.0);
  EXPECT_NEAR(ty0, y0, 2.0);
  EXPECT_NEAR(ty1, y1, 2.0);

  // The press: pixels change around the probe's tip (the dent and the probe in front of it)
  // and along the shaft above it, and hardly anywhere farther than 25 pixels (a sixth of the
  // liver's width) from the tip's column.
  const Eigen::Vector3d tip = scenes::instrument_pose(*scene.instrument, 2.5).translation();
  const Eigen::Vector2d tip_pixel = camera.pixel_of(tip, kWidth, kHeight);
  int near_tip = 0;
  int far = 0;
  int far_total = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::uint8_t* a = image.pixel(x, y);
      const std::uint8_t* b = image.pixel(kWidth + 4 + x, y);
      const bool changed =
          std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]) > 12;
      const double dx = std::abs(x + 0.5 - tip_pixel.x());
      const double dy = std::abs(y + 0.5 - tip_pixel.y());
      if (dx < 12.0 && dy < 12.0) {
        near_tip += changed ? 1 : 0;
      } else if (dx > 25.0) {
        ++far_total;
        far += changed ? 1 : 0;
      }
    }
  }
  EXPECT_GT(near_tip, 40);
  EXPECT_LT(far, far_total / 200) << far << " of " << far_total;
}

}  // namespace
}  // namespace softbench::harness
