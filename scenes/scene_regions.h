// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "scenes/scene.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace softbench::scenes {

/// The fixed vertices of `scene` on `mesh`, sorted and unique; empty for a free body (no fixed
/// region, or one that selects nothing). Throws InputError naming the scene file when an index
/// is out of range.
std::vector<int> fixed_vertices(const Scene& scene, const TetMesh& mesh);
/// fixed_vertices() for a command that cannot run a free body: throws InputError naming the
/// scene file and /fixed, `command` and why it needs the region (`reason`) when it selects none.
std::vector<int> required_fixed_vertices(const Scene& scene,
                                         const TetMesh& mesh,
                                         const std::string& command,
                                         const std::string& reason);

/// A vertex on one or more of the scene's supports: held along their normals, free along the
/// rest (one plane: it slides in it; two: along their line; three: held).
struct SupportedVertex {
  int vertex = -1;
  /// The projector onto the span of the normals of the supports that select it.
  Eigen::Matrix3d held = Eigen::Matrix3d::Zero();
};

/// The vertices the scene's supports select at rest, fixed ones left out, sorted.
std::vector<SupportedVertex> supported_vertices(const Scene& scene, const TetMesh& mesh);

/// The scene's initial velocity on `mesh` (3 x #V, m/s): v_i = linear + angular x (x_i - c) at
/// the rest positions x_i, c the given center or else the centre of mass at rest; zero at the
/// fixed vertices, and everywhere when the scene has no initial velocity.
Eigen::Matrix3Xd initial_velocities(const Scene& scene, const TetMesh& mesh);
/// The centre of mass of `mesh` at rest, m (uniform density: the tets' volume-weighted centroid,
/// which the lumped vertex masses share).
Eigen::Vector3d rest_centre_of_mass(const TetMesh& mesh);

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
