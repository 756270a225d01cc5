// SPDX-License-Identifier: MIT
// Fuzzes scene files: the JSON text through the bounded reader (parse_json_text, as
// read_json_file), the loader and validator (parse_scene), the echo (to_json, which must load
// again: metrics.json's effective scene is a scene), and what the commands derive from a scene
// on a mesh (regions, initial velocities, the grasp and instrument paths), on a small box. The
// scene stands in scenes/, so the shipped scenes' relative mesh paths resolve.
#include "fuzz/fuzz_support.h"
#include "geometry/input_error.h"
#include "geometry/mesh_validation.h"
#include "geometry/shape_meshes.h"
#include "models/json_file.h"
#include "scenes/instrument_path.h"
#include "scenes/scene.h"
#include "scenes/scene_regions.h"
#include "scenes/shipped_data.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace {

namespace fuzz = softbench::fuzz;
namespace scenes = softbench::scenes;

// A 20 cm box about the origin, where the shipped scenes' regions and paths lie.
const softbench::TetMesh& box() {
  static const softbench::TetMesh mesh = [] {
    const std::vector<double> coordinates = {-0.1, -0.05, 0.0, 0.05, 0.1};
    return softbench::make_tet_mesh(
        softbench::grid_box_tets(coordinates, coordinates, coordinates));
  }();
  return mesh;
}

void use_scene(const scenes::Scene& scene) {
  static_cast<void>(scene.num_steps());
  static_cast<void>(scene.release_time());
  static_cast<void>(scene.reference_time());
  static_cast<void>(scenes::fixed_vertices(scene, box()));
  static_cast<void>(scenes::supported_vertices(scene, box()));
  static_cast<void>(scenes::initial_velocities(scene, box()));
  if (scene.grasp) {
    for (const scenes::GraspKeyframe& frame : scene.grasp->path) {
      static_cast<void>(scenes::grasp_offset(*scene.grasp, frame.time));
      static_cast<void>(scenes::grasp_offset(*scene.grasp, 0.5 * frame.time));
    }
  }
  if (scene.instrument) {
    for (const scenes::InstrumentKeyframe& frame : scene.instrument->path) {
      static_cast<void>(scenes::instrument_pose(*scene.instrument, frame.time));
      static_cast<void>(scenes::instrument_pose(*scene.instrument, 0.5 * frame.time));
    }
  }
  static_cast<void>(scenes::grasped_vertices(scene, box()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path source =
      scenes::shipped_data_dir().parent_path() / "fuzz_scene.json";
  const std::string text = fuzz::as_text(data, size);
  fuzz::expect_only_input_errors(source.string(), [&] {
    const scenes::Scene scene = scenes::parse_scene(softbench::parse_json_text(text, source),
                                                    source);
    const nlohmann::json echo = scenes::to_json(scene);
    static_cast<void>(echo.dump());
    try {
      static_cast<void>(scenes::parse_scene(echo, source));
    } catch (const softbench::InputError& error) {
      fuzz::finding(std::string("the echo of a loaded scene does not load: ") + error.what());
    }
    use_scene(scene);
  });
  return 0;
}
