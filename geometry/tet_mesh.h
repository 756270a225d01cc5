// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <utility>

namespace softbench {

struct MeshData;
struct ValidationReport;
class TetMesh;
TetMesh make_tet_mesh(const MeshData& data, ValidationReport* report);

/// A validated tetrahedral mesh: every coordinate finite, every index in range, every vertex used
/// by some tet, every tet of positive, non-negligible volume with its vertices ordered so that
/// (x1 - x0) . ((x2 - x0) x (x3 - x0)) > 0. Only make_tet_mesh() (mesh_validation.h) builds one,
/// so every model can rely on these invariants without checking them again.
class TetMesh {
 public:
  const Eigen::Matrix3Xd& rest_positions() const { return rest_positions_; }  ///< 3 x #V, m
  const Eigen::Matrix4Xi& tets() const { return tets_; }                      ///< 4 x #tets
  int num_vertices() const { return static_cast<int>(rest_positions_.cols()); }
  int num_tets() const { return static_cast<int>(tets_.cols()); }

 private:
  friend TetMesh make_tet_mesh(const MeshData& data, ValidationReport* report);
  TetMesh(Eigen::Matrix3Xd rest_positions, Eigen::Matrix4Xi tets)
      : rest_positions_(std::move(rest_positions)), tets_(std::move(tets)) {}

  Eigen::Matrix3Xd rest_positions_;
  Eigen::Matrix4Xi tets_;
};

}  // namespace softbench
