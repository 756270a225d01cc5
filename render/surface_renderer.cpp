// SPDX-License-Identifier: MIT
#include "render/surface_renderer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <stdexcept>
#include <string>

namespace softbench::render {
namespace {

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 colour;
uniform mat4 view_projection;
uniform mat4 view;
out vec3 eye_normal;
out vec3 eye_position;
out vec3 base;
void main() {
  gl_Position = view_projection * vec4(position, 1.0);
  eye_normal = mat3(view) * normal;
  eye_position = (view * vec4(position, 1.0)).xyz;
  base = colour;
}
)";

// Lights fixed in the eye's frame: the key from the upper left, behind the viewer.
constexpr const char* kFragmentShader = R"(#version 330 core
in vec3 eye_normal;
in vec3 eye_position;
in vec3 base;
uniform vec4 wire;
out vec4 result;
void main() {
  if (wire.a > 0.0) {
    result = wire;
    return;
  }
  vec3 n = normalize(eye_normal);
  vec3 v = normalize(-eye_position);
  if (dot(n, v) < 0.0) n = -n;
  vec3 key = normalize(vec3(-0.4, 0.6, 0.7));
  vec3 fill = normalize(vec3(0.5, -0.2, 0.6));
  float diffuse = 0.65 * max(dot(n, key), 0.0) + 0.25 * max(dot(n, fill), 0.0) + 0.2;
  float specular = 0.2 * pow(max(dot(n, normalize(key + v)), 0.0), 32.0);
  vec3 linear = base * diffuse + vec3(specular);
  result = vec4(pow(clamp(linear, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}
)";

/// Throws the driver's log, after deleting `object`, when its compile or link `status` failed
/// (shaders and programs have the same calls under different names).
void check(GLuint object,
           GLenum status,
           void (*get)(GLuint, GLenum, GLint*),
           void (*log_of)(GLuint, GLsizei, GLsizei*, GLchar*),
           void (*remove)(GLuint),
           const char* failure) {
  GLint ok = 0;
  get(object, status, &ok);
  if (ok == 0) {
    char log[1024] = {};
    log_of(object, sizeof(log), nullptr, log);
    remove(object);
    throw std::runtime_error(std::string("SurfaceRenderer: ") + failure + ": " + log);
  }
}

GLuint compile(GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  check(shader, GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog, glDeleteShader,
        "shader does not compile");
  return shader;
}

}  // namespace

SurfaceRenderer::SurfaceRenderer() {
  const GLuint vertex = compile(GL_VERTEX_SHADER, kVertexShader);
  GLuint fragment = 0;
  try {
    fragment = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  } catch (const std::runtime_error&) {
    glDeleteShader(vertex);
    throw;
  }
  program_ = glCreateProgram();
  glAttachShader(program_, vertex);
  glAttachShader(program_, fragment);
  glLinkProgram(program_);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  check(program_, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram,
        "program does not link");
  view_projection_location_ = glGetUniformLocation(program_, "view_projection");
  view_location_ = glGetUniformLocation(program_, "view");
  wire_location_ = glGetUniformLocation(program_, "wire");

  glGenVertexArrays(1, &vertex_array_);
  glGenBuffers(1, &vertex_buffer_);
  glGenBuffers(1, &index_buffer_);
  glBindVertexArray(vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
  constexpr GLsizei kStride = SurfaceFrame::kFloatsPerVertex * sizeof(float);
  for (GLuint attribute = 0; attribute < 3; ++attribute) {
    glEnableVertexAttribArray(attribute);
    glVertexAttribPointer(attribute, 3, GL_FLOAT, GL_FALSE, kStride,
                          reinterpret_cast<const void*>(3 * attribute * sizeof(float)));
  }
  glBindVertexArray(0);
}

SurfaceRenderer::~SurfaceRenderer() {
  glDeleteBuffers(1, &index_buffer_);
  glDeleteBuffers(1, &vertex_buffer_);
  glDeleteVertexArrays(1, &vertex_array_);
  glDeleteProgram(program_);
}

void SurfaceRenderer::draw(const SurfaceFrame& frame, const Camera& camera, int width,
                           int height) {
  draw(frame, camera, Viewport{0, 0, width, height}, DrawOptions{});
}

void SurfaceRenderer::draw(const SurfaceFrame& frame,
                           const Camera& camera,
                           const Viewport& viewport,
                           const DrawOptions& options) {
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  // The clear stays inside the viewport: two viewports share one window.
  glEnable(GL_SCISSOR_TEST);
  glScissor(viewport.x, viewport.y, viewport.width, viewport.height);
  if (options.clear) {
    glClearColor(kBackground, kBackground, kBackground, 1.0F);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glUseProgram(program_);
  const Eigen::Matrix4f view_projection = camera.view_projection();
  glUniformMatrix4fv(view_projection_location_, 1, GL_FALSE, view_projection.data());
  glUniformMatrix4fv(view_location_, 1, GL_FALSE, camera.view.data());
  glBindVertexArray(vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(frame.vertices.size() * sizeof(float)),
               frame.vertices.data(), GL_STREAM_DRAW);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(frame.indices.size() * sizeof(std::uint32_t)),
               frame.indices.data(), GL_STREAM_DRAW);
  const auto count = static_cast<GLsizei>(frame.indices.size());
  if (options.shaded) {
    glUniform4f(wire_location_, 0.0F, 0.0F, 0.0F, 0.0F);
    // Pushed back a little, so that edges drawn over the faces are not lost in them.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0F, 1.0F);
    glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_POLYGON_OFFSET_FILL);
  }
  if (options.wireframe) {
    glUniform4f(wire_location_, 0.15F, 0.12F, 0.12F, 1.0F);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_SCISSOR_TEST);
}

}  // namespace softbench::render
