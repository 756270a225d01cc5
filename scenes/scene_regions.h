// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "scenes/scene.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace softbench::scenes {

/// The fixed vertices of `scene` on `mesh`, sorted and unique. Throws InputError naming the
/// scene file when an index is out of range or the region selects no vertex.
std::vector<int> fixed_vertices(const Scene& scene, const TetMesh& mesh);

/// The grasped vertices: those of the scene's grasp, else of its instrument's grasp (see
/// surface_vertices_within), else none.
std::vector<int> grasped_vertices(const Scene& scene, const TetMesh& mesh);

/// The boundary-surface vertices within `radius` of `center` at rest, sorted. Throws InputError
/// naming the scene file and `pointer` (the JSON pointer of the block that asked) when none is.
std::vector<int> surface_vertices_within(const Scene& scene,
                                         const TetMesh& mesh,
                                         const Eigen::Vector3d& center,
                                         double radius,
                                         const std::string& pointer);

/// The grasp's displacement at time t: piecewise linear through the keyframes, zero before the
/// first, constant after the last.
Eigen::Vector3d grasp_offset(const Grasp& grasp, double time);

}  // namespace softbench::scenes
