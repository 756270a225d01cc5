// SPDX-License-Identifier: MIT
#include "render/offscreen_context.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/gl.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace softbench::render {

struct OffscreenContext::Impl {
  OSMesaContext context = nullptr;
  std::vector<std::uint8_t> buffer;  ///< RGBA, rows from the top (OSMESA_Y_UP 0)
};

OffscreenContext::OffscreenContext(int width, int height)
    : impl_(std::make_unique<Impl>()), width_(width), height_(height) {
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            24,
                            OSMESA_STENCIL_BITS,
                            0,
                            OSMESA_ACCUM_BITS,
                            0,
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            3,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            3,
                            0};
  impl_->context = OSMesaCreateContextAttribs(attributes, nullptr);
  if (impl_->context == nullptr) {
    throw std::runtime_error("OSMesa could not create an OpenGL 3.3 core context");
  }
  impl_->buffer.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4, 0);
  if (OSMesaMakeCurrent(impl_->context, impl_->buffer.data(), GL_UNSIGNED_BYTE, width, height)
      == 0) {
    OSMesaDestroyContext(impl_->context);
    throw std::runtime_error("OSMesa could not draw into a " + std::to_string(width) + " x "
                             + std::to_string(height) + " buffer");
  }
  OSMesaPixelStore(OSMESA_Y_UP, 0);
}

OffscreenContext::~OffscreenContext() {
  OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
  OSMesaDestroyContext(impl_->context);
}

Image OffscreenContext::read() const {
  glFinish();
  Image image(width_, height_);
  image.rgba = impl_->buffer;
  return image;
}

}  // namespace softbench::render
