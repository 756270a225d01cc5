// SPDX-License-Identifier: MIT
#include "render/offscreen_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace softbench::render {
namespace {

// EGL's surfaceless platform needs no window system: on a machine without a GPU, Mesa draws
// with llvmpipe. Through GLVND, as a window's context does, so the viewer and the pictures
// call the same gl* entry points in one process.
EGLDisplay surfaceless_display() {
  const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) {
    throw std::runtime_error("EGL has no eglGetPlatformDisplayEXT (install libegl-mesa0)");
  }
  EGLDisplay display =
      get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0;
  EGLint minor = 0;
  if (display == EGL_NO_DISPLAY || eglInitialize(display, &major, &minor) == EGL_FALSE) {
    throw std::runtime_error("EGL has no surfaceless display (install libegl-mesa0)");
  }
  return display;
}

}  // namespace

struct OffscreenContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  GLuint framebuffer = 0;
  GLuint colour = 0;
  GLuint depth = 0;
};

OffscreenContext::OffscreenContext(int width, int height)
    : impl_(std::make_unique<Impl>()), width_(width), height_(height) {
  impl_->display = surfaceless_display();
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               3,
                               EGL_CONTEXT_MINOR_VERSION,
                               3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_NONE};
  if (eglBindAPI(EGL_OPENGL_API) == EGL_FALSE
      || (impl_->context = eglCreateContext(impl_->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT,
                                            attributes))
             == EGL_NO_CONTEXT) {
    eglTerminate(impl_->display);
    throw std::runtime_error("EGL could not create an OpenGL 3.3 core context");
  }
  if (eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context)
      == EGL_FALSE) {
    eglDestroyContext(impl_->display, impl_->context);
    eglTerminate(impl_->display);
    throw std::runtime_error("EGL could not make its context current");
  }
  // No default framebuffer without a surface: the pictures are drawn into this one.
  glGenFramebuffers(1, &impl_->framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, impl_->framebuffer);
  glGenRenderbuffers(1, &impl_->colour);
  glBindRenderbuffer(GL_RENDERBUFFER, impl_->colour);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, impl_->colour);
  glGenRenderbuffers(1, &impl_->depth);
  glBindRenderbuffer(GL_RENDERBUFFER, impl_->depth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, impl_->depth);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    release();
    throw std::runtime_error("OpenGL could not draw into a " + std::to_string(width) + " x "
                             + std::to_string(height) + " buffer");
  }
}

OffscreenContext::~OffscreenContext() {
  release();
}

void OffscreenContext::release() {
  if (impl_->context == EGL_NO_CONTEXT) {
    return;
  }
  glDeleteRenderbuffers(1, &impl_->depth);
  glDeleteRenderbuffers(1, &impl_->colour);
  glDeleteFramebuffers(1, &impl_->framebuffer);
  eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(impl_->display, impl_->context);
  eglTerminate(impl_->display);
  impl_->context = EGL_NO_CONTEXT;
}

Image OffscreenContext::read() const {
  return read_framebuffer(width_, height_);
}

Image read_framebuffer(int width, int height) {
  glFinish();
  Image image(width, height);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
  // GL's rows run from the bottom; an Image's from the top.
  const auto row = static_cast<std::size_t>(width) * 4;
  std::vector<std::uint8_t> swap(row);
  for (int top = 0, bottom = height - 1; top < bottom; ++top, --bottom) {
    std::uint8_t* a = image.rgba.data() + static_cast<std::size_t>(top) * row;
    std::uint8_t* b = image.rgba.data() + static_cast<std::size_t>(bottom) * row;
    std::copy(a, a + row, swap.begin());
    std::copy(b, b + row, a);
    std::copy(swap.begin(), swap.end(), b);
  }
  return image;
}

}  // namespace softbench::render
