// SPDX-License-Identifier: MIT
#pragma once

#include "render/image.h"

#include <memory>

namespace softbench::render {

/// An OpenGL 3.3 core context drawing into memory (OSMesa, Mesa's software renderer): pictures
/// without a display or a GPU, the same on every machine that has Mesa. Current on the
/// constructing thread from construction to destruction; one at a time per thread.
class OffscreenContext {
 public:
  /// Throws std::runtime_error when OSMesa cannot make a 3.3 core context of this size.
  OffscreenContext(int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  /// What has been drawn (after glFinish), rows from the top.
  Image read() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int width_;
  int height_;
};

}  // namespace softbench::render
