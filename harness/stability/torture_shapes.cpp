// SPDX-License-Identifier: MIT
#include "harness/stability/torture_shapes.h"

#include "geometry/mesh_data.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace softbench::harness {
namespace {

Eigen::Vector3d centroid(const Eigen::Matrix3Xd& rest) {
  return rest.rowwise().mean();
}

Eigen::Vector3d extents(const Eigen::Matrix3Xd& rest) {
  const Eigen::Matrix<double, 3, 2> box = bounding_box(rest);
  return box.col(1) - box.col(0);
}

// A uniform double in [0, 1) from the generator's 53 high bits: unlike
// std::uniform_real_distribution, the same on every standard library.
double unit_random(std::mt19937_64& generator) {
  return static_cast<double>(generator() >> 11) * 0x1.0p-53;
}

double radius_ratio(const Eigen::Matrix3Xd& positions, const Eigen::Vector4i& tet) {
  Eigen::Matrix4Xi one(4, 1);
  one.col(0) = tet;
  return tet_quality(positions, one).min_radius_ratio;
}

double tet_volume(const Eigen::Matrix3Xd& x, const Eigen::Vector4i& tet) {
  return signed_tet_volume(x.col(tet(0)), x.col(tet(1)), x.col(tet(2)), x.col(tet(3)));
}

// The position of corner `corner` of `tet` moved toward the opposite face's plane, keeping the
// fraction `kept` of its height.
Eigen::Vector3d lowered(const Eigen::Matrix3Xd& x,
                        const Eigen::Vector4i& tet,
                        int corner,
                        double kept) {
  const Eigen::Vector3d apex = x.col(tet(corner));
  const Eigen::Vector3d p0 = x.col(tet((corner + 1) % 4));
  const Eigen::Vector3d p1 = x.col(tet((corner + 2) % 4));
  const Eigen::Vector3d p2 = x.col(tet((corner + 3) % 4));
  const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0).normalized();
  const double height = (apex - p0).dot(normal);  // signed: the apex's side of the face
  return apex - (1.0 - kept) * height * normal;
}

}  // namespace

Eigen::Matrix3Xd squashed_to_plane(const Eigen::Matrix3Xd& rest) {
  Eigen::Index axis = 0;
  extents(rest).minCoeff(&axis);
  Eigen::Matrix3Xd squashed = rest;
  squashed.row(axis).setConstant(centroid(rest)(axis));
  return squashed;
}

Eigen::Matrix3Xd collapsed_to_point(const Eigen::Matrix3Xd& rest,
                                    double radius_fraction,
                                    std::uint64_t seed) {
  const double radius = radius_fraction * extents(rest).norm();
  const Eigen::Vector3d center = centroid(rest);
  std::mt19937_64 generator(seed);
  Eigen::Matrix3Xd collapsed(3, rest.cols());
  for (Eigen::Index i = 0; i < rest.cols(); ++i) {
    Eigen::Vector3d offset;
    do {  // rejection sampling: uniform in the ball
      for (int k = 0; k < 3; ++k) {
        offset(k) = 2.0 * unit_random(generator) - 1.0;
      }
    } while (offset.squaredNorm() > 1.0);
    collapsed.col(i) = center + radius * offset;
  }
  return collapsed;
}

Eigen::Matrix3Xd scrambled(const Eigen::Matrix3Xd& rest, std::uint64_t seed) {
  const Eigen::Matrix<double, 3, 2> box = bounding_box(rest);
  std::mt19937_64 generator(seed);
  Eigen::Matrix3Xd result(3, rest.cols());
  for (Eigen::Index i = 0; i < rest.cols(); ++i) {
    for (int k = 0; k < 3; ++k) {
      result(k, i) = box(k, 0) + unit_random(generator) * (box(k, 1) - box(k, 0));
    }
  }
  return result;
}

Eigen::Matrix3Xd stretched(const Eigen::Matrix3Xd& rest, double factor) {
  Eigen::Index axis = 0;
  extents(rest).maxCoeff(&axis);
  const double center = centroid(rest)(axis);
  Eigen::Matrix3Xd result = rest;
  result.row(axis) = (center + factor * (rest.row(axis).array() - center)).matrix();
  return result;
}

std::optional<Sliver> flatten_one_tet(const TetMesh& mesh,
                                      std::span<const int> keep,
                                      double quality) {
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const Eigen::Matrix4Xi& tets = mesh.tets();
  std::vector<std::vector<int>> vertex_tets(static_cast<std::size_t>(mesh.num_vertices()));
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      vertex_tets[static_cast<std::size_t>(tets(k, t))].push_back(t);
    }
  }
  std::vector<bool> kept(static_cast<std::size_t>(mesh.num_vertices()), false);
  for (const int vertex : keep) {
    kept[static_cast<std::size_t>(vertex)] = true;
  }
  // The smallest volume ratio new / old among the other tets around the moved vertex; <= 0
  // when one inverts (or flattens).
  const auto neighbour_shrink = [&](int tet, int vertex, const Eigen::Vector3d& moved) {
    double worst = INFINITY;
    for (const int other : vertex_tets[static_cast<std::size_t>(vertex)]) {
      if (other == tet) {
        continue;
      }
      Eigen::Vector4i corners = tets.col(other);
      Eigen::Vector3d p[4];
      for (int k = 0; k < 4; ++k) {
        p[k] = corners(k) == vertex ? moved : Eigen::Vector3d(rest.col(corners(k)));
      }
      const double after = signed_tet_volume(p[0], p[1], p[2], p[3]);
      worst = std::min(worst, after / tet_volume(rest, corners));
    }
    return worst;
  };

  int best_tet = -1;
  int best_corner = -1;
  double best_score = 0.0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::Vector4i tet = tets.col(t);
    // Radius ratio falls about as the square of the height: keep sqrt(quality / q0) of it.
    const double kept_fraction = std::sqrt(quality / radius_ratio(rest, tet));
    for (int corner = 0; corner < 4; ++corner) {
      const int vertex = tet(corner);
      if (kept[static_cast<std::size_t>(vertex)]) {
        continue;
      }
      const double score = neighbour_shrink(t, vertex, lowered(rest, tet, corner, kept_fraction));
      if (score > best_score) {
        best_score = score;
        best_tet = t;
        best_corner = corner;
      }
    }
  }
  if (best_tet < 0) {
    return std::nullopt;
  }
  const Eigen::Vector4i tet = tets.col(best_tet);
  const int vertex = tet(best_corner);
  // Bisect the kept height fraction (in log scale) for the requested radius ratio.
  Eigen::Matrix3Xd x = rest;
  double lo = 1e-12;
  double hi = 1.0;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double mid = std::sqrt(lo * hi);
    x.col(vertex) = lowered(rest, tet, best_corner, mid);
    (radius_ratio(x, tet) < quality ? lo : hi) = mid;
  }
  x.col(vertex) = lowered(rest, tet, best_corner, hi);
  if (neighbour_shrink(best_tet, vertex, x.col(vertex)) <= 0.0) {
    return std::nullopt;
  }
  double neighbour_quality = INFINITY;
  for (const int other : vertex_tets[static_cast<std::size_t>(vertex)]) {
    if (other != best_tet) {
      neighbour_quality = std::min(neighbour_quality, radius_ratio(x, tets.col(other)));
    }
  }
  const double moved = (x.col(vertex) - rest.col(vertex)).norm();
  const double sliver_quality = radius_ratio(x, tet);
  return Sliver{make_tet_mesh(MeshData{x, {}, tets, "mesh with one flattened tet"}),
                best_tet,
                vertex,
                moved,
                sliver_quality,
                neighbour_quality};
}

}  // namespace softbench::harness
