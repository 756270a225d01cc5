// SPDX-License-Identifier: MIT
#include "geometry/marching_cubes.h"

#include "geometry/marching_cubes_table.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "tests/test_tolerances.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace softbench {
namespace {

namespace table = marching_cubes_table;
using std::numbers::pi;

// ---------------------------------------------------------------------------------------------
// Tolerances

/// Marching cubes on the distance field of a sphere of radius R with spacing h <= R/25 (thesis
/// accuracy target): the iso-points are within O(h^2 / R) of the sphere and the chords cut
/// inside it, giving volume and area errors of a few tenths of a percent; 1% leaves room.
constexpr double kFineSphereRelativeError = 0.01;
/// Errors O(h^2) drop by 4 when h halves; the samples' alignment with the sphere changes with h,
/// which perturbs the ratio a little, so accept anything clearly better than first order.
constexpr double kSecondOrderRatio = 3.0;
/// Vertex normals from central differences of the sphere's distance field, interpolated along
/// edges whose corner gradients differ by an angle of about h / R: the direction error is
/// O((h / R)^2) rad, about 0.2 degrees at h = R/16 (0.05 measured); 0.5 leaves room.
constexpr double kSphereNormalDegrees = 0.5;
/// Coarse torus (tube radius of 8 samples): same O(h^2) reasoning as the sphere, smaller radius.
constexpr double kTorusRelativeVolumeError = 0.02;
/// Positions rebuilt from float samples: the interpolation parameter t carries float32 rounding
/// of the sample values (2^-24 relative), times the spacing.
constexpr double kFloatSampleRounding = test::kFloat32;

// ---------------------------------------------------------------------------------------------
// Helpers

template <typename Field>
ScalarGrid sample(const Eigen::Vector3i& size,
                  const Eigen::Vector3d& origin,
                  const Eigen::Vector3d& spacing,
                  Field field) {
  ScalarGrid grid;
  grid.size = size;
  grid.origin = origin;
  grid.spacing = spacing;
  grid.values.resize(static_cast<std::size_t>(size.prod()));
  for (int k = 0; k < size.z(); ++k) {
    for (int j = 0; j < size.y(); ++j) {
      for (int i = 0; i < size.x(); ++i) {
        grid.at(i, j, k) = static_cast<float>(field(grid.position(i, j, k)));
      }
    }
  }
  return grid;
}

/// A grid with spacing `h` (scaled per axis by `stretch`) covering the box [-half, half]^3 plus
/// two samples of margin, its origin shifted by fractions of a cell so that no symmetry of the
/// shapes below lines up with the samples.
ScalarGrid sample_around_origin(double half_extent,
                                double h,
                                const auto& field,
                                const Eigen::Vector3d& stretch = Eigen::Vector3d::Ones()) {
  const Eigen::Vector3d spacing = h * stretch;
  const Eigen::Vector3d origin =
      -(Eigen::Vector3d::Constant(half_extent + 2.0 * h) + Eigen::Vector3d(0.31, 0.17, 0.43) * h);
  Eigen::Vector3i size;
  for (int axis = 0; axis < 3; ++axis) {
    size[axis] = static_cast<int>(std::ceil(-2.0 * origin[axis] / spacing[axis])) + 1;
  }
  return sample(size, origin, spacing, field);
}

auto sphere_distance(double radius, const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  return [=](const Eigen::Vector3d& x) { return radius - (x - centre).norm(); };
}

SurfaceTopology topology(const TriMesh& mesh) {
  return surface_topology(mesh.triangles, mesh.num_vertices());
}

void expect_closed_oriented_manifold(const TriMesh& mesh) {
  const SurfaceTopology topo = topology(mesh);
  EXPECT_EQ(topo.boundary_edges, 0);
  EXPECT_EQ(topo.non_manifold_edges, 0);
  EXPECT_EQ(topo.misoriented_edges, 0);
  EXPECT_EQ(topo.unreferenced_vertices, 0);
}

int crossed_grid_edges(const ScalarGrid& grid, float iso) {
  int count = 0;
  for (int k = 0; k < grid.size.z(); ++k) {
    for (int j = 0; j < grid.size.y(); ++j) {
      for (int i = 0; i < grid.size.x(); ++i) {
        const bool inside = grid.at(i, j, k) > iso;
        count += i + 1 < grid.size.x() && inside != (grid.at(i + 1, j, k) > iso);
        count += j + 1 < grid.size.y() && inside != (grid.at(i, j + 1, k) > iso);
        count += k + 1 < grid.size.z() && inside != (grid.at(i, j, k + 1) > iso);
      }
    }
  }
  return count;
}

bool is_inside(int case_index, int corner) {
  return ((case_index >> corner) & 1) != 0;
}

bool is_crossed(int case_index, int edge) {
  return is_inside(case_index, table::kCubeEdges[edge].corner0)
         != is_inside(case_index, table::kCubeEdges[edge].corner1);
}

bool face_has_edge(int face, int edge) {
  const auto& corners = table::kCubeFaces[face];
  auto has = [&](int c) { return std::find(corners.begin(), corners.end(), c) != corners.end(); };
  return has(table::kCubeEdges[edge].corner0) && has(table::kCubeEdges[edge].corner1);
}

using DirectedEdge = std::pair<int, int>;  // (from cube edge, to cube edge)

/// The boundary of a case's triangle patch: directed triangle sides whose reverse is not a side.
std::set<DirectedEdge> patch_boundary(int case_index) {
  const table::CaseTriangles& triangles = table::case_table()[case_index];
  std::multiset<DirectedEdge> sides;
  for (int t = 0; t < triangles.count; ++t) {
    for (int c = 0; c < 3; ++c) {
      sides.emplace(triangles.triangles[t][c], triangles.triangles[t][(c + 1) % 3]);
    }
  }
  std::set<DirectedEdge> boundary;
  for (const auto& [from, to] : sides) {
    if (sides.count({to, from}) == 0) {
      boundary.emplace(from, to);
    }
  }
  return boundary;
}

/// The patch boundary's segments lying on `face`, as pairs of cube corners' edges.
std::set<DirectedEdge> boundary_on_face(int case_index, int face) {
  std::set<DirectedEdge> on_face;
  for (const auto& segment : patch_boundary(case_index)) {
    if (face_has_edge(face, segment.first) && face_has_edge(face, segment.second)) {
      on_face.insert(segment);
    }
  }
  return on_face;
}

int edge_between(int corner_a, int corner_b) {
  for (int e = 0; e < 12; ++e) {
    const auto& edge = table::kCubeEdges[e];
    if (std::minmax(edge.corner0, edge.corner1) == std::minmax(corner_a, corner_b)) {
      return e;
    }
  }
  return -1;
}

// ---------------------------------------------------------------------------------------------
// The case table

TEST(MarchingCubesTable, CornerAndEdgeConventionsAgree) {
  for (int e = 0; e < 12; ++e) {
    const auto& edge = table::kCubeEdges[e];
    const auto a = table::corner_offset(edge.corner0);
    const auto b = table::corner_offset(edge.corner1);
    const std::array<int, 3> step = {b.x - a.x, b.y - a.y, b.z - a.z};
    EXPECT_EQ(step[static_cast<std::size_t>(edge.axis)], 1) << "edge " << e;
    EXPECT_EQ(std::abs(step[0]) + std::abs(step[1]) + std::abs(step[2]), 1) << "edge " << e;
  }
}

TEST(MarchingCubesTable, FacesListTheirCornersCounterClockwiseFromOutside) {
  for (int f = 0; f < 6; ++f) {
    std::array<Eigen::Vector3d, 4> x;
    for (int c = 0; c < 4; ++c) {
      const auto offset = table::corner_offset(table::kCubeFaces[f][c]);
      x[c] = Eigen::Vector3d(offset.x, offset.y, offset.z);
    }
    const int axis = f / 2;
    const double side = f % 2 == 0 ? 0.0 : 1.0;
    Eigen::Vector3d outward = Eigen::Vector3d::Zero();
    outward[axis] = f % 2 == 0 ? -1.0 : 1.0;
    for (int c = 0; c < 4; ++c) {
      EXPECT_EQ(x[c][axis], side) << "face " << f;
      EXPECT_TRUE(
          ((x[(c + 1) % 4] - x[c]).cross(x[(c + 2) % 4] - x[(c + 1) % 4])).isApprox(outward))
          << "face " << f << " corner " << c;
    }
  }
}

TEST(MarchingCubesTable, AllInsideAndAllOutsideCasesAreEmpty) {
  EXPECT_EQ(table::case_table()[0].count, 0);
  EXPECT_EQ(table::case_table()[255].count, 0);
}

TEST(MarchingCubesTable, SingleInsideOrOutsideCornerGivesOneTriangleAroundIt) {
  for (int corner = 0; corner < 8; ++corner) {
    std::set<int> edges_at_corner;
    for (int e = 0; e < 12; ++e) {
      if (table::kCubeEdges[e].corner0 == corner || table::kCubeEdges[e].corner1 == corner) {
        edges_at_corner.insert(e);
      }
    }
    for (int case_index : {1 << corner, 255 ^ (1 << corner)}) {
      const auto& triangles = table::case_table()[case_index];
      ASSERT_EQ(triangles.count, 1) << "case " << case_index;
      const auto& t = triangles.triangles[0];
      EXPECT_EQ(std::set<int>(t.begin(), t.end()), edges_at_corner) << "case " << case_index;
    }
  }
}

TEST(MarchingCubesTable, SingleInsideCornerTriangleFacesAwayFromIt) {
  for (int corner = 0; corner < 8; ++corner) {
    const auto& t = table::case_table()[1 << corner].triangles[0];
    std::array<Eigen::Vector3d, 3> midpoint;
    for (int c = 0; c < 3; ++c) {
      const auto& edge = table::kCubeEdges[t[c]];
      const auto a = table::corner_offset(edge.corner0);
      const auto b = table::corner_offset(edge.corner1);
      midpoint[c] = 0.5 * Eigen::Vector3d(a.x + b.x, a.y + b.y, a.z + b.z);
    }
    const auto offset = table::corner_offset(corner);
    const Eigen::Vector3d away = midpoint[0] - Eigen::Vector3d(offset.x, offset.y, offset.z);
    const Eigen::Vector3d normal = (midpoint[1] - midpoint[0]).cross(midpoint[2] - midpoint[0]);
    EXPECT_GT(normal.dot(away), 0.0) << "corner " << corner;
  }
}

TEST(MarchingCubesTable, TrianglesUseExactlyTheCrossedEdges) {
  for (int case_index = 0; case_index < 256; ++case_index) {
    std::set<int> used;
    const auto& triangles = table::case_table()[case_index];
    for (int t = 0; t < triangles.count; ++t) {
      used.insert(triangles.triangles[t].begin(), triangles.triangles[t].end());
    }
    std::set<int> crossed;
    for (int e = 0; e < 12; ++e) {
      if (is_crossed(case_index, e)) {
        crossed.insert(e);
      }
    }
    EXPECT_EQ(used, crossed) << "case " << case_index;
  }
}

// Each case's triangles must form patches whose boundaries are closed loops of face segments
// (so that neighbouring cells can close them), each loop of n edges filled with n - 2 triangles
// (a disc), and whose inner edges are each shared by exactly two oppositely oriented triangles.
TEST(MarchingCubesTable, EveryCaseFillsClosedLoopsOfFaceSegmentsWithDiscs) {
  for (int case_index = 0; case_index < 256; ++case_index) {
    SCOPED_TRACE("case " + std::to_string(case_index));
    const auto& triangles = table::case_table()[case_index];
    std::map<DirectedEdge, int> side_uses;
    for (int t = 0; t < triangles.count; ++t) {
      const auto& tri = triangles.triangles[t];
      EXPECT_TRUE(tri[0] != tri[1] && tri[1] != tri[2] && tri[2] != tri[0]);
      for (int c = 0; c < 3; ++c) {
        ++side_uses[{tri[c], tri[(c + 1) % 3]}];
      }
    }
    for (const auto& [side, uses] : side_uses) {
      EXPECT_EQ(uses, 1) << "side " << side.first << "->" << side.second << " repeats";
    }

    const std::set<DirectedEdge> boundary = patch_boundary(case_index);
    std::map<int, int> next;
    for (const auto& [from, to] : boundary) {
      bool on_a_face = false;
      for (int f = 0; f < 6; ++f) {
        on_a_face = on_a_face || (face_has_edge(f, from) && face_has_edge(f, to));
      }
      EXPECT_TRUE(on_a_face) << from << "->" << to << " crosses the cube's inside";
      EXPECT_TRUE(next.emplace(from, to).second) << "two boundary segments leave edge " << from;
    }
    // Follow the segments: every crossed edge is left exactly once and entered exactly once.
    int expected_triangles = 0;
    std::set<int> visited;
    for (const auto& [first, unused] : next) {
      if (visited.count(first) != 0) {
        continue;
      }
      int loop_length = 0;
      int edge = first;
      do {
        ASSERT_EQ(next.count(edge), 1u) << "loop through " << first << " is open at " << edge;
        ASSERT_TRUE(visited.insert(edge).second) << "edge " << edge << " entered twice";
        edge = next[edge];
        ++loop_length;
      } while (edge != first);
      expected_triangles += loop_length - 2;
    }
    int crossed = 0;
    for (int e = 0; e < 12; ++e) {
      crossed += is_crossed(case_index, e);
    }
    EXPECT_EQ(static_cast<int>(visited.size()), crossed);
    EXPECT_EQ(triangles.count, expected_triangles);
  }
}

// Two cells sharing a face see the same four face corners; their patches must meet in the same
// segments, traversed in opposite directions (so the joint surface is consistently oriented).
TEST(MarchingCubesTable, CellsSharingAFaceJoinItsEdgesTheSameWayInOppositeDirections) {
  for (int axis = 0; axis < 3; ++axis) {
    const int bit = 1 << axis;
    const int upper_face = 2 * axis + 1;  // of the lower cell
    const int lower_face = 2 * axis;      // of the upper cell
    // Maps the lower cell's edges on its upper face to the same grid edges in the upper cell.
    auto to_upper_cell = [&](int edge) {
      return edge_between(table::kCubeEdges[edge].corner0 ^ bit,
                          table::kCubeEdges[edge].corner1 ^ bit);
    };
    for (int lower = 0; lower < 256; ++lower) {
      for (int upper = 0; upper < 256; ++upper) {
        bool faces_agree = true;
        for (int corner = 0; corner < 8; ++corner) {
          if ((corner & bit) != 0) {
            faces_agree = faces_agree && is_inside(lower, corner) == is_inside(upper, corner ^ bit);
          }
        }
        if (!faces_agree) {
          continue;
        }
        std::set<DirectedEdge> lower_segments_reversed;
        for (const auto& [from, to] : boundary_on_face(lower, upper_face)) {
          lower_segments_reversed.emplace(to_upper_cell(to), to_upper_cell(from));
        }
        EXPECT_EQ(lower_segments_reversed, boundary_on_face(upper, lower_face))
            << "axis " << axis << " cases " << lower << " below " << upper;
      }
    }
  }
}

TEST(MarchingCubesTable, AmbiguousFacesCutOffEachInsideCornerSeparately) {
  int ambiguous_faces_seen = 0;
  for (int case_index = 0; case_index < 256; ++case_index) {
    for (int f = 0; f < 6; ++f) {
      const auto& c = table::kCubeFaces[f];
      for (int first = 0; first < 2; ++first) {
        const int a = c[first];
        const int b = c[first + 2];
        if (!is_inside(case_index, a) || !is_inside(case_index, b)
            || is_inside(case_index, c[1 - first]) || is_inside(case_index, c[3 - first])) {
          continue;
        }
        ++ambiguous_faces_seen;
        std::set<std::set<int>> segments;
        for (const auto& [from, to] : boundary_on_face(case_index, f)) {
          segments.insert({from, to});
        }
        const std::set<std::set<int>> corners_cut_off = {
            {edge_between(a, c[(first + 1) % 4]), edge_between(a, c[(first + 3) % 4])},
            {edge_between(b, c[(first + 1) % 4]), edge_between(b, c[(first + 3) % 4])}};
        EXPECT_EQ(segments, corners_cut_off) << "case " << case_index << " face " << f;
      }
    }
  }
  // Each face is ambiguous in 2 of its 16 sign patterns, times 16 patterns of the other corners.
  EXPECT_EQ(ambiguous_faces_seen, 6 * 2 * 16);
}

// Every case surrounded by outside samples: the case's cell sits in the middle of a 4x4x4 grid.
TEST(MarchingCubesTable, EveryCaseSurroundedByOutsideSamplesGivesAClosedOrientedSurface) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> magnitude(0.1, 1.0);
  for (int case_index = 1; case_index < 256; ++case_index) {
    SCOPED_TRACE("case " + std::to_string(case_index));
    ScalarGrid grid = sample({4, 4, 4}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                             [](const Eigen::Vector3d&) { return -1.0; });
    for (int corner = 0; corner < 8; ++corner) {
      const auto o = table::corner_offset(corner);
      const double sign = is_inside(case_index, corner) ? 1.0 : -1.0;
      grid.at(1 + o.x, 1 + o.y, 1 + o.z) = static_cast<float>(sign * magnitude(random));
    }
    const TriMesh mesh = marching_cubes(grid, 0.0f);
    expect_closed_oriented_manifold(mesh);
    const SurfaceTopology topo = topology(mesh);
    EXPECT_EQ(topo.euler_characteristic, 2 * topo.components);
    EXPECT_GT(enclosed_volume(mesh), 0.0);
  }
}

// ---------------------------------------------------------------------------------------------
// Grid walk

TEST(MarchingCubes, SphereIsAClosedOrientedSurfaceOfGenusZero) {
  for (double cells_per_radius : {3.0, 6.0, 12.0, 24.0}) {
    SCOPED_TRACE("R/h = " + std::to_string(cells_per_radius));
    const double radius = 1.0;
    const ScalarGrid grid =
        sample_around_origin(radius, radius / cells_per_radius, sphere_distance(radius));
    const TriMesh mesh = marching_cubes(grid, 0.0f);
    expect_closed_oriented_manifold(mesh);
    const SurfaceTopology topo = topology(mesh);
    EXPECT_EQ(topo.components, 1);
    EXPECT_EQ(topo.euler_characteristic, 2);
    EXPECT_GT(enclosed_volume(mesh), 0.0) << "triangles face inward";
  }
}

TEST(MarchingCubes, SphereVolumeAndAreaConvergeToTheExactValues) {
  const double radius = 1.0;
  const double exact_volume = 4.0 / 3.0 * pi * radius * radius * radius;
  const double exact_area = 4.0 * pi * radius * radius;
  std::vector<double> volume_errors;
  std::vector<double> area_errors;
  for (double cells_per_radius : {8.0, 16.0, 32.0}) {
    const ScalarGrid grid =
        sample_around_origin(radius, radius / cells_per_radius, sphere_distance(radius));
    const TriMesh mesh = marching_cubes(grid, 0.0f);
    volume_errors.push_back(std::abs(enclosed_volume(mesh) / exact_volume - 1.0));
    area_errors.push_back(std::abs(surface_area(mesh) / exact_area - 1.0));
    const std::string key = "R_over_h_" + std::to_string(static_cast<int>(cells_per_radius));
    testing::Test::RecordProperty(key + "_volume_error", std::to_string(volume_errors.back()));
    testing::Test::RecordProperty(key + "_area_error", std::to_string(area_errors.back()));
  }
  for (std::size_t level = 1; level < volume_errors.size(); ++level) {
    EXPECT_LT(volume_errors[level], volume_errors[level - 1]);
    EXPECT_LT(area_errors[level], area_errors[level - 1]);
    // Second order: halving h should divide the errors by about 4.
    EXPECT_GT(volume_errors[level - 1] / volume_errors[level], kSecondOrderRatio);
    EXPECT_GT(area_errors[level - 1] / area_errors[level], kSecondOrderRatio);
  }
  EXPECT_LT(volume_errors[2], kFineSphereRelativeError);
  EXPECT_LT(area_errors[2], kFineSphereRelativeError);
}

TEST(MarchingCubes, SphereVerticesLieOnTheSphereUpToTheInterpolationError) {
  // Linear interpolation of R - |x| along an edge of length h misplaces the root by at most
  // about h^2 / (2R) (the field's second derivative along the edge is at most 1 / R).
  const double radius = 1.0;
  const double h = radius / 10.0;
  const TriMesh mesh =
      marching_cubes(sample_around_origin(radius, h, sphere_distance(radius)), 0.0f);
  ASSERT_GT(mesh.num_vertices(), 0);
  double worst = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    worst = std::max(worst, std::abs(mesh.vertices.col(v).norm() - radius));
  }
  EXPECT_LT(worst, h * h / (2.0 * radius));
}

TEST(MarchingCubes, SphereNormalsPointRadiallyOutward) {
  const double radius = 1.0;
  Eigen::Matrix3Xd normals;
  const TriMesh mesh = marching_cubes(
      sample_around_origin(radius, radius / 16.0, sphere_distance(radius)), 0.0f, &normals);
  ASSERT_EQ(normals.cols(), mesh.num_vertices());
  double worst_degrees = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    EXPECT_NEAR(normals.col(v).norm(), 1.0, test::kRoundoff);
    const double cosine = normals.col(v).dot(mesh.vertices.col(v).normalized());
    worst_degrees = std::max(worst_degrees, std::acos(std::min(cosine, 1.0)) * 180.0 / pi);
  }
  testing::Test::RecordProperty("worst_normal_degrees", std::to_string(worst_degrees));
  EXPECT_LT(worst_degrees, kSphereNormalDegrees);
}

TEST(MarchingCubes, AnisotropicSpacingStillGivesAnAccurateSphereAndRadialNormals) {
  const double radius = 1.0;
  Eigen::Matrix3Xd normals;
  const ScalarGrid grid = sample_around_origin(radius, radius / 30.0, sphere_distance(radius),
                                               Eigen::Vector3d(1.0, 1.3, 0.8));
  const TriMesh mesh = marching_cubes(grid, 0.0f, &normals);
  expect_closed_oriented_manifold(mesh);
  EXPECT_NEAR(enclosed_volume(mesh), 4.0 / 3.0 * pi, kFineSphereRelativeError * 4.0 / 3.0 * pi);
  double worst_degrees = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double cosine = normals.col(v).dot(mesh.vertices.col(v).normalized());
    worst_degrees = std::max(worst_degrees, std::acos(std::min(cosine, 1.0)) * 180.0 / pi);
  }
  EXPECT_LT(worst_degrees, kSphereNormalDegrees);
}

TEST(MarchingCubes, TorusHasEulerCharacteristicZeroAndTheRightVolume) {
  const double ring_radius = 1.0;
  const double tube_radius = 0.4;
  const auto torus = [&](const Eigen::Vector3d& x) {
    const double from_axis = std::hypot(x.x(), x.y()) - ring_radius;
    return tube_radius - std::hypot(from_axis, x.z());
  };
  const TriMesh mesh = marching_cubes(
      sample_around_origin(ring_radius + tube_radius, tube_radius / 8.0, torus), 0.0f);
  expect_closed_oriented_manifold(mesh);
  const SurfaceTopology topo = topology(mesh);
  EXPECT_EQ(topo.components, 1);
  EXPECT_EQ(topo.euler_characteristic, 0);
  const double exact_volume = 2.0 * pi * pi * ring_radius * tube_radius * tube_radius;
  testing::Test::RecordProperty("volume_error",
                                std::to_string(enclosed_volume(mesh) / exact_volume - 1.0));
  EXPECT_NEAR(enclosed_volume(mesh), exact_volume, kTorusRelativeVolumeError * exact_volume);
}

TEST(MarchingCubes, TwoSeparateSpheresGiveTwoComponents) {
  const Eigen::Vector3d left(-1.0, 0.0, 0.0);
  const Eigen::Vector3d right(1.0, 0.0, 0.0);
  const auto two_balls = [&](const Eigen::Vector3d& x) {
    return std::max(sphere_distance(0.7, left)(x), sphere_distance(0.7, right)(x));
  };
  const TriMesh mesh = marching_cubes(sample_around_origin(1.7, 0.1, two_balls), 0.0f);
  expect_closed_oriented_manifold(mesh);
  const SurfaceTopology topo = topology(mesh);
  EXPECT_EQ(topo.components, 2);
  EXPECT_EQ(topo.euler_characteristic, 4);
  EXPECT_GT(enclosed_volume(mesh), 0.0);
}

// Random samples make every case, ambiguous faces included, appear many times next to every
// other; the border is forced outside so the surface must close.
TEST(MarchingCubes, RandomFieldsAlwaysGiveClosedOrientedManifolds) {
  for (unsigned seed = 0; seed < 40; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    const Eigen::Vector3i size(9 + static_cast<int>(seed % 3), 8, 7 + static_cast<int>(seed % 4));
    ScalarGrid grid = sample(size, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.7, 0.3),
                             [&](const Eigen::Vector3d&) { return value(random); });
    for (int k = 0; k < size.z(); ++k) {
      for (int j = 0; j < size.y(); ++j) {
        for (int i = 0; i < size.x(); ++i) {
          const bool border = i == 0 || j == 0 || k == 0 || i == size.x() - 1 || j == size.y() - 1
                              || k == size.z() - 1;
          if (border) {
            grid.at(i, j, k) = -1.0f;
          }
        }
      }
    }
    const TriMesh mesh = marching_cubes(grid, 0.0f);
    ASSERT_GT(mesh.num_triangles(), 0);
    expect_closed_oriented_manifold(mesh);
    EXPECT_EQ(topology(mesh).euler_characteristic % 2, 0);
    EXPECT_GT(enclosed_volume(mesh), 0.0);
  }
}

// Samples exactly at the iso value are outside; vertices on them coincide and some triangles have
// zero area, but the vertices stay distinct, so the topology is unaffected.
TEST(MarchingCubes, SamplesExactlyAtTheIsoValueKeepTheSurfaceClosed) {
  for (unsigned seed = 0; seed < 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 random(seed);
    std::uniform_int_distribution<int> level(-1, 1);
    const Eigen::Vector3i size(8, 8, 8);
    ScalarGrid grid = sample(
        size, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), [&](const Eigen::Vector3d& x) {
          const bool border = (x.array() == 0.0).any() || (x.array() == 7.0).any();
          return border ? 0.0 : static_cast<double>(level(random));
        });
    const TriMesh mesh = marching_cubes(grid, 0.0f);
    ASSERT_GT(mesh.num_triangles(), 0);
    expect_closed_oriented_manifold(mesh);
    EXPECT_GT(enclosed_volume(mesh), 0.0);
  }
}

TEST(MarchingCubes, MakesOneSharedVertexPerCrossedGridEdge) {
  const ScalarGrid grid = sample_around_origin(1.0, 0.15, sphere_distance(1.0));
  const TriMesh mesh = marching_cubes(grid, 0.0f);
  EXPECT_EQ(mesh.num_vertices(), crossed_grid_edges(grid, 0.0f));
}

TEST(MarchingCubes, LinearFieldPutsVerticesOnTheIsoPlaneAndLeavesTheSheetOpenAtTheBorder) {
  const Eigen::Vector3d normal = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const double offset = 0.37;
  const ScalarGrid grid =
      sample({12, 10, 9}, Eigen::Vector3d(-0.5, -0.4, -0.45), Eigen::Vector3d(0.1, 0.1, 0.1),
             [&](const Eigen::Vector3d& x) { return offset - normal.dot(x); });
  const TriMesh mesh = marching_cubes(grid, 0.25f);
  ASSERT_GT(mesh.num_vertices(), 0);
  const double plane_offset = offset - 0.25;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    EXPECT_NEAR(normal.dot(mesh.vertices.col(v)), plane_offset, kFloatSampleRounding);
  }
  const SurfaceTopology topo = topology(mesh);
  EXPECT_GT(topo.boundary_edges, 0);
  EXPECT_EQ(topo.non_manifold_edges, 0);
  EXPECT_EQ(topo.misoriented_edges, 0);
  EXPECT_EQ(topo.components, 1);
  // The sheet faces the low side: away from the field's increase, along +normal.
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const auto c = mesh.triangles.col(t);
    const Eigen::Vector3d area = (mesh.vertices.col(c(1)) - mesh.vertices.col(c(0)))
                                     .cross(mesh.vertices.col(c(2)) - mesh.vertices.col(c(0)));
    EXPECT_GE(area.dot(normal), 0.0);
  }
}

TEST(MarchingCubes, SampleExactlyAtIsoPutsTheVertexOnTheSample) {
  // Corner (1, 1, 1) inside, its six neighbours exactly at iso: the six vertices sit on them.
  ScalarGrid grid = sample({3, 3, 3}, Eigen::Vector3d(0.5, 0.25, 2.0), Eigen::Vector3d(0.5, 1, 2),
                           [](const Eigen::Vector3d&) { return -1.0; });
  grid.at(1, 1, 1) = 2.0f;
  for (const auto& [i, j, k] : std::vector<std::array<int, 3>>{
           {0, 1, 1}, {2, 1, 1}, {1, 0, 1}, {1, 2, 1}, {1, 1, 0}, {1, 1, 2}}) {
    grid.at(i, j, k) = 0.5f;
  }
  const TriMesh mesh = marching_cubes(grid, 0.5f);
  ASSERT_EQ(mesh.num_vertices(), 6);
  EXPECT_EQ(mesh.num_triangles(), 8);  // an octahedron
  expect_closed_oriented_manifold(mesh);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d cells = (mesh.vertices.col(v) - grid.origin).cwiseQuotient(grid.spacing);
    EXPECT_EQ(cells, cells.array().round().matrix()) << "vertex " << v << " is not on a sample";
  }
  EXPECT_NEAR(enclosed_volume(mesh), 4.0 / 3.0 * 0.5 * 1.0 * 2.0, test::kRoundoff);
}

TEST(MarchingCubes, NormalsFallBackToTheTrianglesWhereTheGradientVanishes) {
  // A checkerboard: the central differences vanish at every inner sample, so between inner
  // samples the interpolated gradient is zero and the triangles' normals must stand in. Each
  // inside sample is wrapped in its own octahedron, so the normal at the vertex between inside
  // sample A and outside sample B points from A to B.
  const ScalarGrid grid =
      sample({6, 6, 6}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
             [](const Eigen::Vector3d& x) { return std::fmod(x.sum(), 2.0) == 0.0 ? 1.0 : -1.0; });
  Eigen::Matrix3Xd normals;
  const TriMesh mesh = marching_cubes(grid, 0.0f, &normals);
  ASSERT_EQ(normals.cols(), mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d x = mesh.vertices.col(v);
    EXPECT_NEAR(normals.col(v).norm(), 1.0, test::kRoundoff) << "vertex " << v;
    // x is the midpoint of a grid edge; its inside end is the one with an even coordinate sum.
    const Eigen::Vector3d lower_end = x.array().floor();
    const Eigen::Vector3d upper_end = x.array().ceil();
    const bool lower_inside = std::fmod(lower_end.sum(), 2.0) == 0.0;
    const Eigen::Vector3d inside_to_outside =
        lower_inside ? upper_end - lower_end : lower_end - upper_end;
    EXPECT_GT(normals.col(v).dot(inside_to_outside), 0.0) << "vertex " << v;
  }
}

TEST(MarchingCubes, IsoValueOutsideTheSampleRangeGivesAnEmptyMesh) {
  const ScalarGrid grid = sample_around_origin(1.0, 0.25, sphere_distance(1.0));
  Eigen::Matrix3Xd normals(3, 5);
  const TriMesh mesh = marching_cubes(grid, 100.0f, &normals);
  EXPECT_EQ(mesh.num_vertices(), 0);
  EXPECT_EQ(mesh.num_triangles(), 0);
  EXPECT_EQ(normals.cols(), 0);
  EXPECT_EQ(marching_cubes(grid, -100.0f).num_triangles(), 0);
}

TEST(MarchingCubes, GridThinnerThanOneCellGivesAnEmptyMesh) {
  const ScalarGrid grid = sample({5, 1, 5}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                                 [](const Eigen::Vector3d& x) { return x.x() - 2.5; });
  EXPECT_EQ(marching_cubes(grid, 0.0f).num_triangles(), 0);
}

TEST(MarchingCubes, InconsistentGridsAreRejected) {
  ScalarGrid grid = sample({3, 3, 3}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                           [](const Eigen::Vector3d&) { return 0.0; });
  ScalarGrid short_values = grid;
  short_values.values.pop_back();
  EXPECT_THROW(marching_cubes(short_values, 0.0f), std::invalid_argument);
  ScalarGrid mirrored = grid;
  mirrored.spacing.y() = -1.0;
  EXPECT_THROW(marching_cubes(mirrored, 0.0f), std::invalid_argument);
  ScalarGrid not_a_number = grid;
  not_a_number.at(1, 1, 1) = std::nanf("");
  EXPECT_THROW(marching_cubes(not_a_number, 0.0f), std::invalid_argument);
  EXPECT_THROW(marching_cubes(grid, std::nanf("")), std::invalid_argument);
}

TEST(MarchingCubes, OutputIsDeterministic) {
  const ScalarGrid grid = sample_around_origin(1.0, 0.1, sphere_distance(1.0));
  Eigen::Matrix3Xd normals_a;
  Eigen::Matrix3Xd normals_b;
  const TriMesh a = marching_cubes(grid, 0.0f, &normals_a);
  const TriMesh b = marching_cubes(grid, 0.0f, &normals_b);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(normals_a, normals_b);
}

}  // namespace
}  // namespace softbench
