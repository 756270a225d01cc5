// SPDX-License-Identifier: MIT
#include "harness/report/pictures.h"

#include "scenes/instrument_path.h"

#include <algorithm>
#include <stdexcept>

#if SOFTBENCH_WITH_RENDER
#include "render/image.h"
#include "render/offscreen_context.h"
#include "render/surface_frame.h"
#include "render/surface_renderer.h"
#endif

namespace softbench::harness {

#if SOFTBENCH_WITH_RENDER

bool pictures_available() { return true; }

render::Camera pictures_camera(const SceneMesh& mesh,
                               double aspect,
                               const Eigen::Vector3d& direction,
                               double zoom) {
  // At the rest shape with room around it for the loads' moves (the pull's 4 cm on the 15 cm
  // liver). Not at the box of every picture: one model stretched into a spike half a metre long
  // would shrink every other model's liver to a few pixels; a shape that wild may leave the
  // frame.
  const Eigen::Vector3d lower = mesh.body.rest_positions().rowwise().minCoeff();
  const Eigen::Vector3d upper = mesh.body.rest_positions().rowwise().maxCoeff();
  return render::camera_on_box(lower, upper, direction, aspect, 1.2 * zoom);
}

void write_pictures(const std::filesystem::path& path,
                    const scenes::Scene& scene,
                    const SceneMesh& mesh,
                    const std::vector<ModelRun>& runs,
                    std::size_t columns,
                    int tile_width,
                    int tile_height) {
  constexpr int kSupersample = 2;
  constexpr int kGap = 4;
  if (columns == 0 || runs.empty()) {
    throw std::runtime_error(path.string() + ": no picture to draw");
  }
  const render::Camera camera =
      pictures_camera(mesh, static_cast<double>(tile_width) / tile_height);

  render::OffscreenContext context(tile_width * kSupersample, tile_height * kSupersample);
  render::SurfaceRenderer renderer;
  const render::BodySurface surface(mesh.body);
  const auto count = static_cast<int>(columns);
  const auto count_rows = static_cast<int>(runs.size());
  render::Image canvas(count * tile_width + (count - 1) * kGap,
                       count_rows * tile_height + (count_rows - 1) * kGap);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    for (std::size_t c = 0; c < std::min(columns, runs[r].pictures.size()); ++c) {
      const Snapshot& picture = runs[r].pictures[c];
      render::SurfaceFrame frame;
      surface.append(picture.positions, frame);
      if (scene.instrument && mesh.instrument) {
        render::append_instrument(*mesh.instrument,
                                  scenes::instrument_pose(*scene.instrument, picture.time), frame);
      }
      renderer.draw(frame, camera, context.width(), context.height());
      render::paste(render::downsample(context.read(), kSupersample),
                    static_cast<int>(c) * (tile_width + kGap),
                    static_cast<int>(r) * (tile_height + kGap), canvas);
    }
  }
  render::write_png(path, canvas);
}

#else

bool pictures_available() { return false; }

void write_pictures(const std::filesystem::path&,
                    const scenes::Scene&,
                    const SceneMesh&,
                    const std::vector<ModelRun>&,
                    std::size_t,
                    int,
                    int) {
  throw std::runtime_error("this build draws no pictures (configured without SOFTBENCH_WITH_RENDER)");
}

#endif

}  // namespace softbench::harness
