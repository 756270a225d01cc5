// SPDX-License-Identifier: MIT
// The harness tests' small scene: a 10 x 2 x 2 cm bar (30 tets) clamped at x = 0, stiff enough
// (50 kPa) that edge springs alone bring it back (a softer one folds, which mass-spring cannot
// undo), sagging under gravity for 0.5 s, then released: gravity off.
#pragma once

#include "geometry/mesh_io.h"
#include "scenes/scene.h"
#include "tests/test_meshes.h"

#include <string>

namespace softbench::harness::test_scenes {

/// Writes the bar's mesh and the scene into `dir` and loads it, with `models_block` (a JSON
/// object) as its models, `dt` and `duration` in seconds.
inline scenes::Scene bar_sag(const test::TempDir& dir,
                             const std::string& models_block,
                             double dt = 1.0 / 60.0,
                             double duration = 3.0) {
  write_msh(dir.path() / "bar.msh", test::box_tets(5, 1, 1, 0.1, 0.02, 0.02));
  const std::string text = R"({
      "name": "bar_sag",
      "mesh": "bar.msh",
      "material": {"young_modulus": 50000, "poisson_ratio": 0.3, "density": 1000},
      "gravity": {"acceleration": [0, 0, -9.81], "off_at": 0.5},
      "time": {"dt": )" + std::to_string(dt) + R"(, "duration": )" + std::to_string(duration)
                           + R"(},
      "fixed": {"box": {"min": [-0.001, -1, -1], "max": [0.001, 1, 1]}},
      "models": )" + models_block + "}";
  return scenes::load_scene(dir.write("bar_sag.json", text));
}

}  // namespace softbench::harness::test_scenes
