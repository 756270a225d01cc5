// SPDX-License-Identifier: MIT
#pragma once

#include "render/image.h"

#include <memory>

namespace softbench::render {

/// An OpenGL 3.3 core context drawing into a framebuffer of its own (EGL's surfaceless
/// platform: Mesa's software renderer where there is no GPU): pictures without a display, the
/// same on every machine that has Mesa. Current on the
/// constructing thread from construction to destruction; one at a time per thread.
class OffscreenContext {
 public:
  /// Throws std::runtime_error when EGL cannot make a 3.3 core context of this size.
  OffscreenContext(int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  /// What has been drawn (after glFinish), rows from the top.
  Image read() const;

 private:
  void release();
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int width_;
  int height_;
};

/// What the current context's bound framebuffer holds in (0, 0, width, height), after
/// glFinish, rows from the top: a picture's pixels, or a window's screenshot.
Image read_framebuffer(int width, int height);

}  // namespace softbench::render
