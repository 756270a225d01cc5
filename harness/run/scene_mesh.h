// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "geometry/tri_mesh.h"
#include "scenes/scene.h"

#include <memory>
#include <string>

namespace softbench::harness {

/// A scene's meshes, read and checked once per command and shared by every run of it: the body
/// and, with an instrument, the tool's closed surface.
struct SceneMesh {
  TetMesh body;
  /// stable_hash of the body's mesh file: what cache keys and sweep ids name the mesh by, so
  /// results on two meshes never mix.
  std::string content_hash;
  std::shared_ptr<const TriMesh> instrument;  ///< null without an instrument

  double diagonal() const;  ///< m, the rest bounding-box diagonal
};

/// Reads scene.mesh (and the instrument's mesh). Throws InputError naming the file, also when the
/// body's mesh is far from the size the scene expects: its bounding-box diagonal more than 20x
/// larger than what the scene's fixed box (within the mesh's box), grasp and instrument path
/// (and the tool itself) span, or more than 20x smaller than the first three, the mark of a mesh
/// in millimetres for a scene in metres or the other way round. A scene with none of those (a
/// fixed plane or vertex list only) is not checked.
SceneMesh read_scene_mesh(const scenes::Scene& scene);

}  // namespace softbench::harness
