// SPDX-License-Identifier: MIT
#pragma once

#include "harness/run/scene_mesh.h"
#include "scenes/scene.h"
#include "viewer/input_script.h"
#include "viewer/live_model.h"

#include <filesystem>
#include <string>
#include <vector>

namespace softbench::viewer {

struct ViewOptions {
  std::vector<std::string> models;  ///< one viewport each, side by side (one or two)
  int width = 1280;                 ///< the window, in screen pixels
  int height = 720;
  Drive drive = Drive::kHand;
  std::vector<InputEvent> input;  ///< scripted input, replayed as a person's
  std::filesystem::path report;   ///< written at the end (JSON): frame rate, each model's pace
};

/// The interactive liver: a window (GLFW, OpenGL 3.3 core) with Dear ImGui controls, one
/// LiveModel per viewport on its own thread, the hand's instrument moved with the mouse (drag
/// on the body: press; G: grasp and pull; right drag: turn; wheel: zoom), until the window is
/// closed, the script quits, or Ctrl-C (harness::interrupt_requested() then says so). Throws
/// InputError when no window can be opened (no display) and for a bad model block.
void run_viewer(const scenes::Scene& scene,
                const harness::SceneMesh& mesh,
                const ViewOptions& options);

}  // namespace softbench::viewer
