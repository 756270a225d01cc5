// SPDX-License-Identifier: MIT
// The offscreen renderer: a box drawn where its camera says, a press changing the pixels where
// the box was pressed and nowhere else, inverted tets marked, PNGs written and read back.
#include "render/camera.h"
#include "render/image.h"
#include "render/offscreen_context.h"
#include "render/surface_frame.h"
#include "render/surface_renderer.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "tests/test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace softbench::render {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;
constexpr int kSupersample = 2;

/// 8 x 4 x 4 cm in 1 cm cells, its corner at the origin.
const TetMesh& box() {
  static const TetMesh mesh = make_tet_mesh(test::box_tets(8, 4, 4, 0.08, 0.04, 0.04));
  return mesh;
}

Camera box_camera() {
  return camera_on_box(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.08, 0.04, 0.04),
                       Eigen::Vector3d(0.3, -1.0, 0.6), static_cast<double>(kWidth) / kHeight);
}

Image draw(const Eigen::Matrix3Xd& positions) {
  OffscreenContext context(kWidth * kSupersample, kHeight * kSupersample);
  SurfaceRenderer renderer;
  SurfaceFrame frame;
  BodySurface(box()).append(positions, frame);
  renderer.draw(frame, box_camera(), context.width(), context.height());
  return downsample(context.read(), kSupersample);
}

bool is_background(const std::uint8_t* p) {
  const int ground = static_cast<int>(std::lround(kBackground * 255.0));
  return std::abs(p[0] - ground) <= 1 && std::abs(p[1] - ground) <= 1 &&
         std::abs(p[2] - ground) <= 1;
}

struct PixelBox {
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  void add(const Eigen::Vector2d& p) {
    x0 = std::min(x0, p.x());
    y0 = std::min(y0, p.y());
    x1 = std::max(x1, p.x());
    y1 = std::max(y1, p.y());
  }
};

TEST(Render, TheRestBoxFillsTheSilhouetteItsCornersProjectTo) {
  const Image image = draw(box().rest_positions());
  // Where the 8 corners land: the drawn pixels' bounds, within a pixel (anti-aliased edges).
  PixelBox expected;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p((corner & 1) * 0.08, ((corner >> 1) & 1) * 0.04,
                            ((corner >> 2) & 1) * 0.04);
    expected.add(box_camera().pixel_of(p, kWidth, kHeight));
  }
  PixelBox drawn;
  int covered = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (!is_background(image.pixel(x, y))) {
        drawn.add(Eigen::Vector2d(x + 0.5, y + 0.5));
        ++covered;
      }
    }
  }
  EXPECT_NEAR(drawn.x0, expected.x0, 1.5);
  EXPECT_NEAR(drawn.x1, expected.x1, 1.5);
  EXPECT_NEAR(drawn.y0, expected.y0, 1.5);
  EXPECT_NEAR(drawn.y1, expected.y1, 1.5);
  // The box covers a large share of its bounds (a hexagon in its bounding rectangle), and its
  // centre is the tissue's colour, lit: red above green and blue.
  EXPECT_GT(covered, 0.5 * (expected.x1 - expected.x0) * (expected.y1 - expected.y0));
  const Eigen::Vector2d centre = box_camera().pixel_of(Eigen::Vector3d(0.04, 0.02, 0.02),
                                                       kWidth, kHeight);
  const std::uint8_t* p = image.pixel(static_cast<int>(centre.x()), static_cast<int>(centre.y()));
  EXPECT_GT(p[0], p[1] + 40);
  EXPECT_GT(p[0], p[2] + 40);
}

TEST(Render, APressChangesThePixelsWhereTheBoxWasPressedAndNowhereElse) {
  const Image rest = draw(box().rest_positions());
  // A 1 cm dent in the top face around (2 cm, 2 cm): the top vertices within 1 cm go down by
  // up to 1 cm (a cone).
  Eigen::Matrix3Xd pressed = box().rest_positions();
  const Eigen::Vector2d spot(0.02, 0.02);
  PixelBox moved;
  for (int v = 0; v < box().num_vertices(); ++v) {
    const double distance = (pressed.col(v).head<2>() - spot).norm();
    if (pressed(2, v) > 0.04 - 1e-9 && distance < 0.0101) {
      pressed(2, v) -= 0.01 * (1.0 - distance / 0.0101);
      moved.add(box_camera().pixel_of(pressed.col(v), kWidth, kHeight));
      moved.add(box_camera().pixel_of(box().rest_positions().col(v), kWidth, kHeight));
    }
  }
  const Image dented = draw(pressed);
  // Shading changes on the faces around the moved vertices too: allow their one-cell ring
  // (1 cm across, ~15 pixels here).
  constexpr double kRing = 16.0;
  int changed_inside = 0;
  int changed_outside = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::uint8_t* a = rest.pixel(x, y);
      const std::uint8_t* b = dented.pixel(x, y);
      const bool changed =
          std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]) > 6;
      if (!changed) {
        continue;
      }
      const bool near = x + 0.5 > moved.x0 - kRing && x + 0.5 < moved.x1 + kRing &&
                        y + 0.5 > moved.y0 - kRing && y + 0.5 < moved.y1 + kRing;
      ++(near ? changed_inside : changed_outside);
    }
  }
  EXPECT_GT(changed_inside, 50);
  EXPECT_EQ(changed_outside, 0);
}

TEST(Render, InvertedTetsAreMarkedInTheirColour) {
  Eigen::Matrix3Xd positions = box().rest_positions();
  // Push one top-face vertex 3 cm down through the box: the tets around it invert.
  int top = -1;
  for (int v = 0; v < box().num_vertices(); ++v) {
    if ((positions.col(v) - Eigen::Vector3d(0.04, 0.02, 0.04)).norm() < 1e-9) {
      top = v;
    }
  }
  ASSERT_GE(top, 0);
  positions(2, top) -= 0.03;
  EXPECT_GT(count_inverted_tets(box(), positions), 0);
  EXPECT_EQ(count_inverted_tets(box(), box().rest_positions()), 0);
  // The surface counts what it marks: the viewer shows that number.
  SurfaceFrame frame;
  EXPECT_EQ(BodySurface(box()).append(positions, frame), count_inverted_tets(box(), positions));
  const Image image = draw(positions);
  int marked = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      marked += (p[0] > 150 && p[1] > 120 && p[2] < 90) ? 1 : 0;  // yellow, lit
    }
  }
  EXPECT_GT(marked, 5);
}

TEST(Render, APngReadsBackAsWritten) {
  Image image(7, 5);
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 7; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(30 * x);
      p[1] = static_cast<std::uint8_t>(50 * y);
      p[2] = 77;
    }
  }
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "softbench_render_test.png";
  write_png(path, image);
  const Image back = read_png(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  EXPECT_EQ(back.rgba, image.rgba);
}

}  // namespace
}  // namespace softbench::render

namespace softbench::render {
namespace {

// A click picks the surface point under it: the ray through the pixel a point of the top face
// lands on meets the surface at that point (within 1e-6 m, float matrices), on the top face
// (normal +z), and the hit's weights give the point back from its triangle's corners.
TEST(Render, AClickPicksTheSurfacePointUnderIt) {
  const Camera camera = box_camera();
  const BodySurface surface(box());
  const Eigen::Vector3d on_top(0.031, 0.017, 0.04);
  const Ray ray = camera.ray_through(camera.pixel_of(on_top, kWidth, kHeight), kWidth, kHeight);
  const std::optional<SurfaceHit> hit = surface.pick(box().rest_positions(), ray);
  ASSERT_TRUE(hit.has_value());
  EXPECT_LT((hit->point - on_top).norm(), 1e-6);
  EXPECT_GT(hit->normal.z(), 0.999);
  Eigen::Vector3d from_weights = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    from_weights += hit->weights[k] * box().rest_positions().col(hit->vertices[static_cast<std::size_t>(k)]);
  }
  EXPECT_LT((from_weights - hit->point).norm(), 1e-9);
  // A ray that passes beside the box picks nothing.
  const Ray beside = camera.ray_through(Eigen::Vector2d(1.0, 1.0), kWidth, kHeight);
  EXPECT_FALSE(surface.pick(box().rest_positions(), beside).has_value());
}

}  // namespace
}  // namespace softbench::render
