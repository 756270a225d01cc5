// SPDX-License-Identifier: MIT
#include "harness/report/pictures.h"

#include "scenes/instrument_path.h"

#include <cmath>
#include <stdexcept>

#if SOFTBENCH_WITH_RENDER
#include "render/image.h"
#include "render/offscreen_context.h"
#include "render/surface_frame.h"
#include "render/surface_renderer.h"
#endif

namespace softbench::harness {

std::vector<std::vector<Picture>> picture_rows(const std::vector<ModelRun>& runs,
                                               const std::vector<double>& times) {
  std::vector<std::vector<Picture>> rows;
  for (const ModelRun& run : runs) {
    std::vector<Picture>& row = rows.emplace_back();
    for (std::size_t k = 0; k < times.size(); ++k) {
      row.push_back(k < run.pictures.size()
                        ? Picture{times[k], run.pictures[k].positions}
                        : Picture{times[k], Eigen::Matrix3Xd::Constant(3, 1, std::nan(""))});
    }
  }
  return rows;
}

#if SOFTBENCH_WITH_RENDER

bool pictures_available() { return true; }

render::Camera pictures_camera(const SceneMesh& mesh, double aspect) {
  // From the front (+y: anterior on the scenes' livers), above and to the right, at the rest
  // shape with room around it for the loads' moves (the pull's 4 cm on the 15 cm liver). Not
  // at the box of every picture: one model stretched into a spike half a metre long would
  // shrink every other model's liver to a few pixels; a shape that wild may leave the frame.
  const Eigen::Vector3d direction(0.35, 0.9, 1.2);
  const Eigen::Vector3d lower = mesh.body.rest_positions().rowwise().minCoeff();
  const Eigen::Vector3d upper = mesh.body.rest_positions().rowwise().maxCoeff();
  return render::camera_on_box(lower, upper, direction, aspect, 1.2);
}

void write_pictures(const std::filesystem::path& path,
                    const scenes::Scene& scene,
                    const SceneMesh& mesh,
                    const std::vector<std::vector<Picture>>& rows,
                    int tile_width,
                    int tile_height) {
  constexpr int kSupersample = 2;
  constexpr int kGap = 4;
  std::size_t columns = 0;
  for (const std::vector<Picture>& row : rows) {
    columns = std::max(columns, row.size());
  }
  if (columns == 0) {
    throw std::runtime_error(path.string() + ": no picture to draw");
  }
  const render::Camera camera =
      pictures_camera(mesh, static_cast<double>(tile_width) / tile_height);

  render::OffscreenContext context(tile_width * kSupersample, tile_height * kSupersample);
  render::SurfaceRenderer renderer;
  const render::BodySurface surface(mesh.body);
  const auto count = static_cast<int>(columns);
  render::Image canvas(count * tile_width + (count - 1) * kGap,
                       static_cast<int>(rows.size()) * tile_height
                           + (static_cast<int>(rows.size()) - 1) * kGap);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t c = 0; c < rows[r].size(); ++c) {
      const Picture& picture = rows[r][c];
      if (!picture.positions.allFinite()) {
        continue;
      }
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
                    const std::vector<std::vector<Picture>>&,
                    int,
                    int) {
  throw std::runtime_error("this build draws no pictures (configured without SOFTBENCH_WITH_RENDER)");
}

#endif

}  // namespace softbench::harness
