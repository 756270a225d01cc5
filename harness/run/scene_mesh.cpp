// SPDX-License-Identifier: MIT
#include "harness/run/scene_mesh.h"

#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "harness/provenance.h"

namespace softbench::harness {

double SceneMesh::diagonal() const {
  const Eigen::Matrix<double, 3, 2> box = bounding_box(body.rest_positions());
  return (box.col(1) - box.col(0)).norm();
}

SceneMesh read_scene_mesh(const scenes::Scene& scene) {
  std::shared_ptr<const TriMesh> instrument;
  if (scene.instrument) {
    instrument =
        std::make_shared<const TriMesh>(make_closed_surface(read_mesh(scene.instrument->mesh)));
  }
  return {make_tet_mesh(read_mesh(scene.mesh)), file_hash(scene.mesh.string()),
          std::move(instrument)};
}

}  // namespace softbench::harness
