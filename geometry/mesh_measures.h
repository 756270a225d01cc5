// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>

namespace softbench {

/// Signed volume (x1 - x0) . ((x2 - x0) x (x3 - x0)) / 6; positive for the TetMesh orientation.
double signed_tet_volume(const Eigen::Vector3d& x0,
                         const Eigen::Vector3d& x1,
                         const Eigen::Vector3d& x2,
                         const Eigen::Vector3d& x3);

/// Whether tet t of `tets` has a signed volume <= 0 at `positions` (3 x #V): inverted or flat.
bool is_inverted(const Eigen::Matrix4Xi& tets, Eigen::Index t, const Eigen::Matrix3Xd& positions);
/// Tets whose signed volume at `positions` (3 x #V) is <= 0.
int count_inverted_tets(const TetMesh& mesh, const Eigen::Matrix3Xd& positions);

/// Volume of a tet mesh at `positions` (3 x #V; the rest positions if omitted), m^3.
double mesh_volume(const TetMesh& mesh);
double mesh_volume(const TetMesh& mesh, const Eigen::Matrix3Xd& positions);

/// Volume enclosed by a closed surface by the divergence theorem; positive when outward oriented.
double enclosed_volume(const TriMesh& surface);
double surface_area(const TriMesh& surface);

/// Axis-aligned bounds of a point set (3 x #V): column 0 the minimum, column 1 the maximum.
Eigen::Matrix<double, 3, 2> bounding_box(const Eigen::Matrix3Xd& points);
/// Length of the bounding box's diagonal (m): the size a body's displacements and residuals are
/// measured against. 0 for no point.
double bounding_box_diagonal(const Eigen::Matrix3Xd& points);

/// Lumped vertex masses (kg, #V): each tet's mass density * volume split equally among its four
/// vertices. Sums to density * mesh_volume(mesh).
Eigen::VectorXd lumped_masses(const TetMesh& mesh, double density);

/// Shape quality of the tets. Radius ratio is 3 r_in / r_circ (1 for a regular tet, 0 for a
/// flat one); dihedral angles in degrees (70.53 for a regular tet).
struct TetQuality {
  double min_dihedral_deg = 0.0;
  double max_dihedral_deg = 0.0;
  double min_radius_ratio = 0.0;
  double median_radius_ratio = 0.0;
  double mean_radius_ratio = 0.0;
};
TetQuality tet_quality(const Eigen::Matrix3Xd& positions, const Eigen::Matrix4Xi& tets);

}  // namespace softbench
