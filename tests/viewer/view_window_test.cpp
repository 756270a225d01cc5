// SPDX-License-Identifier: MIT
// `softbench view` as a person uses it, on a virtual display (Xvfb, Mesa's software GL): the
// liver_press scene with corotational_fem, a scripted press at a point of the liver, and the
// window's own screenshots before and during the press. The liver is on screen; the press
// changes the liver's pixels where it pressed and nowhere else; the window kept 50 frames a
// second or more while the model ran in real time beside it.
#include "render/image.h"
#include "tests/test_meshes.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <string>

namespace softbench {
namespace {

constexpr int kWidth = 800;
constexpr int kHeight = 600;
/// Where the script presses: the right lobe's front, in the default view of liver_press.
constexpr int kPressX = 420;
constexpr int kPressY = 300;
/// The contact region: pixels within this of the press (the probe's tip pushes a dimple about
/// 2 cm across, some 60 pixels at this distance, and drags the surface around it).
constexpr int kContactRadius = 100;
/// The control panel sits in the top band, each viewport's figures in the bottom one: their text
/// changes every frame.
constexpr int kPanelBand = 240;
constexpr int kFiguresBand = 110;

bool tissue(const std::uint8_t* p) {
  return p[0] > p[2] + 30;  // the tissue is red; the ground grey, the instrument bluish grey
}

bool differs(const std::uint8_t* a, const std::uint8_t* b) {
  for (int c = 0; c < 3; ++c) {
    if (std::abs(a[c] - b[c]) > 30) {
      return true;
    }
  }
  return false;
}

TEST(ViewWindow, APressDeformsTheLiverWhereItPressedAndTheWindowKeepsFiftyFramesASecond) {
  ASSERT_STRNE(SOFTBENCH_XVFB_RUN, "") << "xvfb-run not found at configure time (install xvfb "
                                          "and xauth: scripts/setup does)";
  const test::TempDir dir;
  const std::filesystem::path rest = dir.path() / "rest.png";
  const std::filesystem::path pressed = dir.path() / "pressed.png";
  const std::filesystem::path report = dir.path() / "report.json";
  // Settled by 2.5 s (the scene's mass damping, 5 /s); a press 60 pixels deep (about 2 cm) at
  // 3 s; the pressed picture 2.5 s later.
  const nlohmann::json input = {
      {"events",
       {{{"t", 2.5}, {"screenshot", rest.string()}},
        {{"t", 3.0}, {"mouse_down", {kPressX, kPressY}}},
        {{"t", 3.1}, {"mouse_move", {kPressX, kPressY + 30}}},
        {{"t", 3.3}, {"mouse_move", {kPressX, kPressY + 60}}},
        {{"t", 5.5}, {"screenshot", pressed.string()}},
        {{"t", 6.0}, {"quit", true}}}}};
  const std::filesystem::path script = dir.write("input.json", input.dump());
  const std::string command = std::string(SOFTBENCH_XVFB_RUN) +
                              " -a -s '-screen 0 1024x768x24' " + SOFTBENCH_EXECUTABLE +
                              " view scenes/liver_press.json --model corotational_fem --width " +
                              std::to_string(kWidth) + " --height " + std::to_string(kHeight) +
                              " --input " + script.string() + " --report " + report.string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  const render::Image before = render::read_png(rest);
  const render::Image after = render::read_png(pressed);
  ASSERT_EQ(before.width, kWidth);
  ASSERT_EQ(before.height, kHeight);
  ASSERT_EQ(after.width, kWidth);
  // The liver is on screen, under the point pressed.
  int liver = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      liver += tissue(before.pixel(x, y)) ? 1 : 0;
    }
  }
  EXPECT_GT(liver, kWidth * kHeight / 20) << "the liver covers under 5% of the window";
  EXPECT_TRUE(tissue(before.pixel(kPressX, kPressY)));

  int near = 0;
  int near_changed = 0;
  int far = 0;
  int far_changed = 0;
  for (int y = kPanelBand; y < kHeight - kFiguresBand; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const int dx = x - kPressX;
      const int dy = y - kPressY;
      const bool changed = differs(before.pixel(x, y), after.pixel(x, y));
      if (dx * dx + dy * dy <= kContactRadius * kContactRadius) {
        ++near;
        near_changed += changed ? 1 : 0;
      } else {
        ++far;
        // The liver's pixels (in either picture) that changed: the instrument's shaft, which
        // reaches out of the contact region, is not the liver's.
        far_changed += changed && (tissue(before.pixel(x, y)) || tissue(after.pixel(x, y))) ? 1 : 0;
      }
    }
  }
  // Measured (2026-12-02): 12.3% of the contact region changed, 0.47% of the rest (817 of
  // 172,977 pixels: the lobe gives a little under a 2 cm press and its outline moves by a
  // pixel). The bound is twice that: a press that moved or broke the whole liver changes tens
  // of percent there.
  EXPECT_GT(near_changed, near / 20) << near_changed << " of " << near;
  EXPECT_LT(far_changed, far / 100) << far_changed << " of " << far;

  std::ifstream in(report);
  const nlohmann::json measured = nlohmann::json::parse(in);
  // The rate the window showed, second by second: its median (the first second is the window's
  // start-up).
  EXPECT_GE(measured.at("frames_per_second_shown_median").get<double>(), 50.0) << measured.dump(2);
  const nlohmann::json& model = measured.at("viewports").at(0);
  EXPECT_EQ(model.at("model"), "corotational_fem");
  EXPECT_EQ(model.at("failure"), "");
  // The physics kept real time beside the window: 6 s of wall time, about as much simulated.
  EXPECT_GT(model.at("time").get<double>(), 5.0);
}

}  // namespace
}  // namespace softbench
