// SPDX-License-Identifier: MIT
#include "geometry/mesh_measures.h"

#include "geometry/mesh_validation.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace softbench {
namespace {

using test::box_tets;
using test::cube_five_tets;
using test::cube_surface;
using test::single_tet;

// Angles come out of acos of dot products carrying round-off; away from 0 and 180 degrees acos
// amplifies that by only O(1), so a few round-off units in degrees.
constexpr double kAngleDeg = 1e-9;
// A tet whose apex sits this far above the opposite face, relative to its edges.
constexpr double kFlatHeight = 1e-6;

double degrees(double radians) {
  return radians * 180.0 / std::numbers::pi;
}

// A regular tet with edge 2 sqrt(2): alternate corners of the cube [-1, 1]^3.
Eigen::Matrix3Xd regular_tet_positions() {
  Eigen::Matrix3Xd x(3, 4);
  x << 1, 1, -1, -1,  //
      1, -1, 1, -1,   //
      1, -1, -1, 1;
  return x;
}

Eigen::Matrix4Xi first_tet() {
  return Eigen::Vector4i(0, 1, 2, 3);
}

TEST(SignedTetVolume, OfTheUnitRightTetIsOneSixthAndChangesSignWithAnOddPermutation) {
  const Eigen::Vector3d o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);

  EXPECT_NEAR(signed_tet_volume(o, x, y, z), 1.0 / 6.0, test::kRoundoff);
  EXPECT_NEAR(signed_tet_volume(o, y, x, z), -1.0 / 6.0, test::kRoundoff);
}

TEST(MeshVolume, OfASingleTetIsOneSixth) {
  EXPECT_NEAR(mesh_volume(make_tet_mesh(single_tet())), 1.0 / 6.0, test::kRoundoff);
}

TEST(MeshVolume, OfABoxIsTheBoxVolume) {
  EXPECT_NEAR(mesh_volume(make_tet_mesh(box_tets(3, 2, 2, 2.0, 1.0, 1.0))), 2.0, test::kRoundoff);
  EXPECT_NEAR(mesh_volume(make_tet_mesh(cube_five_tets())), 1.0, test::kRoundoff);
}

TEST(MeshVolume, AtDeformedPositionsScalesWithTheCubeOfTheStretch) {
  const TetMesh box = make_tet_mesh(box_tets(2, 2, 2));
  const Eigen::Matrix3Xd doubled = 2.0 * box.rest_positions();

  EXPECT_NEAR(mesh_volume(box, doubled), 8.0, test::kRoundoff);
}

TEST(EnclosedVolume, OfTheCubeSurfaceIsOneAndNegativeWhenInsideOut) {
  TriMesh cube{cube_surface().vertices, cube_surface().triangles};
  EXPECT_NEAR(enclosed_volume(cube), 1.0, test::kRoundoff);

  cube.triangles.row(1).swap(cube.triangles.row(2));
  EXPECT_NEAR(enclosed_volume(cube), -1.0, test::kRoundoff);
}

TEST(EnclosedVolume, DoesNotDependOnWhereTheSurfaceIs) {
  // Far from the origin the divergence-theorem sum cancels large terms unless it is referred to
  // a nearby point; 1e6 m away the cancellation would lose ~12 digits.
  TriMesh cube{cube_surface().vertices, cube_surface().triangles};
  cube.vertices.colwise() += Eigen::Vector3d(1e6, -2e6, 3e6);

  EXPECT_NEAR(enclosed_volume(cube), 1.0, test::kRoundoff);
}

TEST(SurfaceArea, OfTheUnitCubeIsSix) {
  const TriMesh cube{cube_surface().vertices, cube_surface().triangles};

  EXPECT_NEAR(surface_area(cube), 6.0, test::kRoundoff);
}

TEST(BoundingBox, SpansTheBoxAndIsZeroForNoPoints) {
  const Eigen::Matrix<double, 3, 2> box = bounding_box(box_tets(3, 2, 2, 2.0, 1.0, 0.5).vertices);

  EXPECT_EQ(box.col(0), Eigen::Vector3d(0.0, 0.0, 0.0));
  EXPECT_EQ(box.col(1), Eigen::Vector3d(2.0, 1.0, 0.5));
  EXPECT_EQ(bounding_box(Eigen::Matrix3Xd(3, 0)), (Eigen::Matrix<double, 3, 2>::Zero()));
}

TEST(LumpedMasses, GiveEachVertexOfASingleTetAQuarter) {
  const double density = 1000.0;
  const Eigen::VectorXd masses = lumped_masses(make_tet_mesh(single_tet()), density);

  ASSERT_EQ(masses.size(), 4);
  for (int v = 0; v < 4; ++v) {
    EXPECT_NEAR(masses(v), density / 6.0 / 4.0, density * test::kRoundoff) << v;
  }
}

TEST(LumpedMasses, SumToDensityTimesVolume) {
  const double density = 1070.0;  // kg/m^3, soft tissue
  const TetMesh box = make_tet_mesh(box_tets(3, 2, 2, 0.2, 0.1, 0.1));
  const Eigen::VectorXd masses = lumped_masses(box, density);

  EXPECT_NEAR(masses.sum(), density * mesh_volume(box), density * test::kRoundoff);
  EXPECT_GT(masses.minCoeff(), 0.0);
}

TEST(TetQuality, OfARegularTetIsPerfect) {
  const TetQuality quality = tet_quality(regular_tet_positions(), first_tet());
  const double regular_dihedral = degrees(std::acos(1.0 / 3.0));

  EXPECT_NEAR(regular_dihedral, 70.5288, 1e-4);
  EXPECT_NEAR(quality.min_dihedral_deg, regular_dihedral, kAngleDeg);
  EXPECT_NEAR(quality.max_dihedral_deg, regular_dihedral, kAngleDeg);
  EXPECT_NEAR(quality.min_radius_ratio, 1.0, test::kRoundoff);
  EXPECT_NEAR(quality.median_radius_ratio, 1.0, test::kRoundoff);
  EXPECT_NEAR(quality.mean_radius_ratio, 1.0, test::kRoundoff);
}

TEST(TetQuality, OfTheUnitRightTetHasRightAndObliqueDihedrals) {
  // Right angles at the three edges through the origin; at the other three the faces meet at
  // acos(1/sqrt(3)). r_in = 1 / (3 + sqrt(3)), r_circ = sqrt(3) / 2.
  const MeshData tet = single_tet();
  const TetQuality quality = tet_quality(tet.vertices, tet.tetrahedra);

  EXPECT_NEAR(quality.min_dihedral_deg, degrees(std::acos(1.0 / std::sqrt(3.0))), kAngleDeg);
  EXPECT_NEAR(quality.max_dihedral_deg, 90.0, kAngleDeg);
  EXPECT_NEAR(quality.min_radius_ratio, 3.0 / (3.0 + std::sqrt(3.0)) / (std::sqrt(3.0) / 2.0),
              test::kRoundoff);
}

TEST(TetQuality, OfAFlattenedTetHasARadiusRatioNearZero) {
  Eigen::Matrix3Xd x = regular_tet_positions();
  // Put the first vertex almost into the plane of the other three.
  const Eigen::Vector3d centroid = (x.col(1) + x.col(2) + x.col(3)) / 3.0;
  const Eigen::Vector3d normal = (x.col(2) - x.col(1)).cross(x.col(3) - x.col(1)).normalized();
  x.col(0) = centroid + kFlatHeight * normal;
  const TetQuality quality = tet_quality(x, first_tet());

  EXPECT_LT(quality.min_radius_ratio, 10 * kFlatHeight);
  EXPECT_GE(quality.min_radius_ratio, 0.0);
  EXPECT_GT(quality.max_dihedral_deg, 179.9);
}

TEST(TetQuality, DoesNotChangeUnderRigidMotionAndUniformScaling) {
  const MeshData box = box_tets(3, 2, 2, 2.0, 1.0, 0.7);
  const Eigen::Affine3d motion = Eigen::Translation3d(4.0, -3.0, 2.5)
                                 * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())
                                 * Eigen::Scaling(3.7);
  const Eigen::Matrix3Xd moved = motion * box.vertices;

  const TetQuality before = tet_quality(box.vertices, box.tetrahedra);
  const TetQuality after = tet_quality(moved, box.tetrahedra);

  EXPECT_NEAR(after.min_dihedral_deg, before.min_dihedral_deg, kAngleDeg);
  EXPECT_NEAR(after.max_dihedral_deg, before.max_dihedral_deg, kAngleDeg);
  EXPECT_NEAR(after.min_radius_ratio, before.min_radius_ratio, test::kRoundoff);
  EXPECT_NEAR(after.median_radius_ratio, before.median_radius_ratio, test::kRoundoff);
  EXPECT_NEAR(after.mean_radius_ratio, before.mean_radius_ratio, test::kRoundoff);
}

TEST(TetQuality, DoesNotDependOnTetOrientation) {
  const Eigen::Matrix3Xd x = regular_tet_positions();
  const TetQuality positive = tet_quality(x, first_tet());
  const TetQuality inverted = tet_quality(x, Eigen::Vector4i(1, 0, 2, 3));

  EXPECT_NEAR(inverted.min_radius_ratio, positive.min_radius_ratio, test::kRoundoff);
  EXPECT_NEAR(inverted.min_dihedral_deg, positive.min_dihedral_deg, kAngleDeg);
}

TEST(TetQuality, SummarizesTheRadiusRatiosOfManyTets) {
  // Two regular tets and a flat one: vertex 4 is the centroid of the face (1, 2, 3).
  Eigen::Matrix3Xd x(3, 5);
  x << regular_tet_positions(), regular_tet_positions().rightCols<3>().rowwise().mean();
  Eigen::Matrix4Xi odd(4, 3);
  odd << 0, 1, 1,  //
      1, 0, 2,     //
      2, 2, 3,     //
      3, 3, 4;
  const TetQuality three = tet_quality(x, odd);

  EXPECT_NEAR(three.min_radius_ratio, 0.0, test::kRoundoff);
  EXPECT_NEAR(three.median_radius_ratio, 1.0, test::kRoundoff);
  EXPECT_NEAR(three.mean_radius_ratio, 2.0 / 3.0, test::kRoundoff);

  // With an even count the median is the mean of the two middle values.
  const TetQuality two = tet_quality(x, odd.rightCols<2>());
  EXPECT_NEAR(two.median_radius_ratio, 0.5, test::kRoundoff);
}

TEST(TetQuality, OfNoTetsIsAllZeros) {
  const TetQuality quality = tet_quality(Eigen::Matrix3Xd(3, 0), Eigen::Matrix4Xi(4, 0));

  EXPECT_EQ(quality.min_dihedral_deg, 0.0);
  EXPECT_EQ(quality.max_dihedral_deg, 0.0);
  EXPECT_EQ(quality.min_radius_ratio, 0.0);
  EXPECT_EQ(quality.median_radius_ratio, 0.0);
  EXPECT_EQ(quality.mean_radius_ratio, 0.0);
}

}  // namespace
}  // namespace softbench
