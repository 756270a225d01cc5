// SPDX-License-Identifier: MIT
#pragma once

#include "render/camera.h"
#include "render/surface_frame.h"

namespace softbench::render {

/// A rectangle of the framebuffer in pixels, from its lower left corner (OpenGL's convention).
struct Viewport {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
};

struct DrawOptions {
  bool clear = true;       ///< clear the viewport to the ground first (off: draw over it)
  bool shaded = true;      ///< the lit faces
  bool wireframe = false;  ///< every triangle's edges, dark, over the faces
};

/// Draws a SurfaceFrame with OpenGL 3.3 core into the current context's framebuffer: shaded
/// (a key light, a fill light, ambient and a little specular, in the eye's frame so every picture
/// is lit alike), both faces of every triangle lit (an inside-out region shows, in its colour,
/// instead of vanishing), depth-tested, on a light grey ground. Needs a current context for its
/// whole life (OffscreenContext, or a window's).
class SurfaceRenderer {
 public:
  /// Throws std::runtime_error when the shaders do not compile or link (the driver's log).
  SurfaceRenderer();
  ~SurfaceRenderer();
  SurfaceRenderer(const SurfaceRenderer&) = delete;
  SurfaceRenderer& operator=(const SurfaceRenderer&) = delete;

  /// Clears the viewport (0, 0, width, height) and draws `frame` seen by `camera`.
  void draw(const SurfaceFrame& frame, const Camera& camera, int width, int height);
  /// Draws `frame` seen by `camera` into `viewport` only (clear and all), as `options` say.
  void draw(const SurfaceFrame& frame,
            const Camera& camera,
            const Viewport& viewport,
            const DrawOptions& options);

 private:
  unsigned program_ = 0;
  unsigned vertex_array_ = 0;
  unsigned vertex_buffer_ = 0;
  unsigned index_buffer_ = 0;
  int view_projection_location_ = -1;
  int view_location_ = -1;
  int wire_location_ = -1;
};

/// The ground the renderer clears to (grey level, 0..1).
inline constexpr float kBackground = 0.97F;

}  // namespace softbench::render
