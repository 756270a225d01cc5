// SPDX-License-Identifier: MIT
#include "harness/report/comparison_pictures.h"

#include "harness/format.h"
#include "harness/report/pictures.h"
#include "harness/run/accuracy.h"
#include "harness/run/scene_mesh.h"

#include <stdexcept>

namespace softbench::harness {
namespace {

std::vector<std::string> labels(const std::vector<ModelRun>& runs) {
  std::vector<std::string> result;
  for (const ModelRun& run : runs) {
    result.push_back(run.model);
  }
  return result;
}

}  // namespace

void draw_comparison_pictures(const std::filesystem::path& out_dir,
                              const std::vector<scenes::Scene>& scenes,
                              Comparison& comparison,
                              std::ostream& progress) {
  if (!pictures_available()) {
    return;
  }
  try {
    for (std::size_t i = 0; i < scenes.size() && i < comparison.scenes.size(); ++i) {
      const scenes::Scene& scene = scenes[i];
      const SceneMesh mesh = read_scene_mesh(scene);
      const std::vector<double> times = picture_times(scene);
      const auto draw = [&](const std::vector<ModelRun>& runs, const std::string& table) {
        const std::string file = "pictures_" + folder_name(scene.name) + "_" + table + ".png";
        write_pictures(out_dir / file, scene, mesh, runs, times.size());
        comparison.pictures.push_back({scene.name, table, file, times, labels(runs)});
      };
      draw(comparison.scenes[i].runs, "A");
      for (const MatchedScene& matched : comparison.matched) {
        if (matched.name == scene.name) {
          draw(matched.runs, "B");
        }
      }
    }
  } catch (const std::runtime_error& error) {
    // InputError (a file that cannot be written) is a runtime_error too: the folder is ours
    // and staged, so that is the machine's fault here, not the input's.
    progress << "compare: no pictures (" << error.what() << ")\n";
    comparison.pictures.clear();
  }
}

void pictures_markdown(std::ostream& out, const Comparison& comparison) {
  if (comparison.pictures.empty()) {
    return;
  }
  out << "## Pictures\n\nEach model's liver at the same instants, seen by the same camera: when "
         "the instrument or grasp lets go (the deepest press, the end of the pull) and at the "
         "end of the recovery. Tissue in its colour, the surface of inverted tets in yellow, "
         "the instrument in grey; a blank tile is a run that blew up before that time.\n\n";
  for (const ComparisonPicture& picture : comparison.pictures) {
    out << "### " << picture.scene << ", table " << picture.table << "\n\nRows, top to bottom:";
    for (std::size_t k = 0; k < picture.rows.size(); ++k) {
      out << " " << picture.rows[k] << (k + 1 == picture.rows.size() ? "." : ",");
    }
    out << " Columns:";
    for (std::size_t k = 0; k < picture.times.size(); ++k) {
      out << " " << picture.times[k] << " s" << (k + 1 == picture.times.size() ? "." : ",");
    }
    out << "\n\n![" << picture.scene << ", table " << picture.table << "](" << picture.file
        << ")\n\n";
  }
}

}  // namespace softbench::harness
