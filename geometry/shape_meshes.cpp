// SPDX-License-Identifier: MIT
#include "geometry/shape_meshes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace softbench {
namespace {

void check_axis(const std::vector<double>& coordinates, const char* axis) {
  if (coordinates.size() < 2) {
    throw std::invalid_argument(std::string("grid_box_tets: fewer than two ") + axis
                                + " coordinates");
  }
  for (std::size_t i = 1; i < coordinates.size(); ++i) {
    if (!(coordinates[i] > coordinates[i - 1])) {
      throw std::invalid_argument(std::string("grid_box_tets: ") + axis
                                  + " coordinates not strictly increasing");
    }
  }
}

}  // namespace

MeshData grid_box_tets(const std::vector<double>& xs,
                       const std::vector<double>& ys,
                       const std::vector<double>& zs) {
  check_axis(xs, "x");
  check_axis(ys, "y");
  check_axis(zs, "z");
  const int px = static_cast<int>(xs.size());
  const int py = static_cast<int>(ys.size());
  const int pz = static_cast<int>(zs.size());
  const auto vertex_index = [&](int i, int j, int k) { return i + px * (j + py * k); };
  MeshData mesh;
  mesh.vertices.resize(3, static_cast<Eigen::Index>(px) * py * pz);
  for (int k = 0; k < pz; ++k) {
    for (int j = 0; j < py; ++j) {
      for (int i = 0; i < px; ++i) {
        mesh.vertices.col(vertex_index(i, j, k)) << xs[static_cast<std::size_t>(i)],
            ys[static_cast<std::size_t>(j)], zs[static_cast<std::size_t>(k)];
      }
    }
  }
  // Kuhn's split: the six tets along the main diagonal, one per ordering of the axes.
  const int axis_orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const Eigen::Index cells = static_cast<Eigen::Index>(px - 1) * (py - 1) * (pz - 1);
  mesh.tetrahedra.resize(4, 6 * cells);
  Eigen::Index t = 0;
  for (int k = 0; k + 1 < pz; ++k) {
    for (int j = 0; j + 1 < py; ++j) {
      for (int i = 0; i + 1 < px; ++i) {
        for (const auto& order : axis_orders) {
          Eigen::Vector3i corner(i, j, k);
          Eigen::Vector4i tet;
          tet(0) = vertex_index(corner.x(), corner.y(), corner.z());
          for (int step = 0; step < 3; ++step) {
            corner(order[step]) += 1;
            tet(step + 1) = vertex_index(corner.x(), corner.y(), corner.z());
          }
          // Half the orderings are odd permutations and give negatively oriented tets.
          const Eigen::Vector3d a = mesh.vertices.col(tet(1)) - mesh.vertices.col(tet(0));
          const Eigen::Vector3d b = mesh.vertices.col(tet(2)) - mesh.vertices.col(tet(0));
          const Eigen::Vector3d c = mesh.vertices.col(tet(3)) - mesh.vertices.col(tet(0));
          if (a.dot(b.cross(c)) < 0) {
            std::swap(tet(2), tet(3));
          }
          mesh.tetrahedra.col(t++) = tet;
        }
      }
    }
  }
  mesh.source = "grid_box_tets";
  return mesh;
}

MeshData box_tets(int nx, int ny, int nz, double lx, double ly, double lz) {
  if (nx < 1 || ny < 1 || nz < 1) {
    throw std::invalid_argument("box_tets: every axis needs at least one cell");
  }
  const auto axis = [](int n, double length) {
    std::vector<double> coordinates(static_cast<std::size_t>(n + 1));
    for (int i = 0; i <= n; ++i) {
      coordinates[static_cast<std::size_t>(i)] = length * i / n;
    }
    return coordinates;
  };
  MeshData mesh = grid_box_tets(axis(nx, lx), axis(ny, ly), axis(nz, lz));
  mesh.source = "box_tets";
  return mesh;
}

TriMesh icosphere(int levels, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriMesh mesh;
  mesh.vertices.resize(3, 12);
  mesh.vertices << -1, 1, -1, 1, 0, 0, 0, 0, t, t, -t, -t,  //
      t, t, -t, -t, -1, 1, -1, 1, 0, 0, 0, 0,               //
      0, 0, 0, 0, t, t, -t, -t, -1, 1, -1, 1;
  mesh.triangles.resize(3, 20);
  mesh.triangles << 0, 0, 0, 0, 0, 1, 5, 11, 10, 7, 3, 3, 3, 3, 3, 4, 2, 6, 8, 9,  //
      11, 5, 1, 7, 10, 5, 11, 10, 7, 1, 9, 4, 2, 6, 8, 9, 4, 2, 6, 8,              //
      5, 1, 7, 10, 11, 9, 4, 2, 6, 8, 4, 2, 6, 8, 9, 5, 11, 10, 7, 1;
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    std::vector<Eigen::Vector3d> vertices;
    for (Eigen::Index i = 0; i < mesh.vertices.cols(); ++i) {
      vertices.push_back(mesh.vertices.col(i));
    }
    const auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = midpoint.try_emplace(key, static_cast<int>(vertices.size()));
      if (inserted) {
        vertices.push_back(
            0.5 * (vertices[static_cast<std::size_t>(a)] + vertices[static_cast<std::size_t>(b)]));
      }
      return it->second;
    };
    Eigen::Matrix3Xi triangles(3, 4 * mesh.triangles.cols());
    for (Eigen::Index f = 0; f < mesh.triangles.cols(); ++f) {
      const int a = mesh.triangles(0, f), b = mesh.triangles(1, f), c = mesh.triangles(2, f);
      const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      triangles.col(4 * f) << a, ab, ca;
      triangles.col(4 * f + 1) << b, bc, ab;
      triangles.col(4 * f + 2) << c, ca, bc;
      triangles.col(4 * f + 3) << ab, bc, ca;
    }
    mesh.triangles = triangles;
    mesh.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      mesh.vertices.col(static_cast<Eigen::Index>(i)) = vertices[i];
    }
  }
  for (Eigen::Index i = 0; i < mesh.vertices.cols(); ++i) {
    mesh.vertices.col(i) = radius * mesh.vertices.col(i).normalized();
  }
  return mesh;
}

}  // namespace softbench
