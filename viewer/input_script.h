// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace softbench::viewer {

/// One scripted input: what a person would do at `time` (s of wall time after the window's
/// first frame). Pixels are the window's, from its top left corner (as the mouse reports them).
struct InputEvent {
  enum class Kind { kMouseDown, kMouseMove, kMouseUp, kKey, kScreenshot, kQuit };
  double time = 0.0;
  Kind kind = Kind::kQuit;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  ///< mouse events
  char key = 0;                                     ///< kKey: a lower-case letter or ' '
  std::filesystem::path file;                       ///< kScreenshot: the PNG to write
};

/// The most events a script may hold: hours of scripted input, and a bound on what it allocates.
inline constexpr int kMaxInputEvents = 100000;

/// Reads a viewer input script, `{"events": [{"t": 2.0, "mouse_down": [400, 300]}, ...]}`, one
/// action per event: "mouse_down", "mouse_move" ([x, y] pixels), "mouse_up": true, "key" (one
/// letter, or "space"), "screenshot" (a PNG path), "quit": true. Events are sorted by time.
/// Throws InputError naming the file and the event's key for anything else.
std::vector<InputEvent> read_input_script(const std::filesystem::path& path);

}  // namespace softbench::viewer
