// SPDX-License-Identifier: MIT
#include "harness/run/mesh_override.h"

#include "geometry/input_error.h"

#include <system_error>

namespace softbench::harness {

void override_mesh(scenes::Scene& scene, const std::filesystem::path& mesh) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(mesh, error)) {
    throw InputError("--mesh " + mesh.string() + ": file not found");
  }
  scene.mesh = mesh.lexically_normal();
}

}  // namespace softbench::harness
