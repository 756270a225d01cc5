// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace softbench::harness {

/// What `softbench mesh info` reports about one mesh file. Counts follow the thesis's (section
/// 2.5.5: "1206 vertices, 4230 tets, 9313 triangles, 6288 edges"), so a generated liver can be
/// compared with it directly.
struct MeshInfo {
  std::string source;
  int vertices = 0;
  int triangles = 0;  ///< the file's triangles, or the tet boundary's if it has none
  bool triangles_from_boundary = false;
  int tetrahedra = 0;
  int faces = 0;  ///< distinct triangular faces of the tets (0 without tets)
  int edges = 0;  ///< distinct edges of the tets, else of the triangles
  Eigen::Matrix<double, 3, 2> bbox = Eigen::Matrix<double, 3, 2>::Zero();
  std::optional<double> volume;  ///< of the tets, or enclosed by a closed surface
  std::optional<double> surface_area;
  SurfaceTopology surface;            ///< of `triangles`
  std::optional<TetQuality> quality;  ///< with tets only
  std::vector<MeshProblem> problems;

  /// No error-severity problem: the mesh can be simulated (tets) or collided with (surface).
  bool usable() const;
};

/// Inspects a mesh as read from a file: never throws for geometric problems, it lists them.
MeshInfo inspect_mesh(const MeshData& data);

nlohmann::json to_json(const MeshInfo& info);
/// Human-readable, one fact per line: "vertices: 1206", "tetrahedra: 4230", ...
std::string to_text(const MeshInfo& info);

}  // namespace softbench::harness
