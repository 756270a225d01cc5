// SPDX-License-Identifier: MIT
#pragma once

#include "harness/run/runner.h"
#include "harness/run/scene_mesh.h"
#include "scenes/scene.h"

#include <Eigen/Core>

#if SOFTBENCH_WITH_RENDER
#include "render/camera.h"
#endif

#include <filesystem>
#include <string>
#include <vector>

namespace softbench::harness {

// Pictures of deformed bodies: what `softbench snapshot` writes and compare.md shows, drawn by
// render/ offscreen (EGL, surfaceless), every picture of a scene seen by the same camera so that models
// and instants compare at a glance. The tissue is drawn in its colour, the surface vertices of
// inverted tets in yellow, the instrument in grey where the scene has it at that time.

/// Whether this build draws pictures (render/ built: SOFTBENCH_WITH_RENDER).
bool pictures_available();

/// Draws each run's ModelRun::pictures (taken at RunOptions::picture_times) as one row of
/// `columns` tiles into one PNG at `path` (written atomically): tiles of `tile_width` x
/// `tile_height` pixels, 2x supersampled, a 4-pixel gap; the tiles of the times a run did not
/// reach (it blew up before) are left blank. The
/// camera looks from the front, above and to the right of the scene's body, at its rest shape
/// with a margin (pictures_camera). Throws InputError naming the file when it cannot
/// be written, std::runtime_error when this build or machine cannot draw.
void write_pictures(const std::filesystem::path& path,
                    const scenes::Scene& scene,
                    const SceneMesh& mesh,
                    const std::vector<ModelRun>& runs,
                    std::size_t columns,
                    int tile_width = 480,
                    int tile_height = 360);

#if SOFTBENCH_WITH_RENDER
/// Where write_pictures looks from (from the body's centre towards the eye): the front (+y:
/// anterior on the scenes' livers), above and to the right.
inline const Eigen::Vector3d kPicturesDirection(0.35, 0.9, 1.2);
/// The camera write_pictures uses for `mesh`'s body in tiles of aspect width / height (the
/// viewer's too, turned to `direction` and moved back by `zoom`).
render::Camera pictures_camera(const SceneMesh& mesh,
                               double aspect,
                               const Eigen::Vector3d& direction = kPicturesDirection,
                               double zoom = 1.0);
#endif

}  // namespace softbench::harness
