// SPDX-License-Identifier: MIT
#include "geometry/mesh_topology.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace softbench {
namespace {

using Triangle = std::array<int, 3>;
using Edge = std::pair<int, int>;  // (smaller, larger)

// The faces of a positively oriented tet (x0..x3), each counter-clockwise seen from outside. Face
// i is opposite vertex i. For the unit tet (0,0,0) (1,0,0) (0,1,0) (0,0,1): face (1,2,3) has normal
// (1,1,1), away from x0; face (0,2,1) has normal (0,0,-1), away from x3; and so on.
constexpr int kOutwardFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// The same triangle, started at its smallest index. A rotation keeps the orientation, so sorting
// rotated triangles gives an order that depends on the surface only, not on the input order.
Triangle smallest_first(const Triangle& t) {
  const auto smallest = std::min_element(t.begin(), t.end()) - t.begin();
  return {t[smallest], t[(smallest + 1) % 3], t[(smallest + 2) % 3]};
}

Eigen::Matrix3Xi to_matrix(const std::vector<Triangle>& triangles) {
  Eigen::Matrix3Xi result(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      result(k, static_cast<Eigen::Index>(t)) = triangles[t][k];
    }
  }
  return result;
}

Eigen::Matrix2Xi to_matrix(const std::vector<Edge>& edges) {
  Eigen::Matrix2Xi result(2, static_cast<Eigen::Index>(edges.size()));
  for (std::size_t e = 0; e < edges.size(); ++e) {
    result(0, static_cast<Eigen::Index>(e)) = edges[e].first;
    result(1, static_cast<Eigen::Index>(e)) = edges[e].second;
  }
  return result;
}

// Every pair of corners of every cell is an edge; cells are triangles or tets.
template <int Corners>
Eigen::Matrix2Xi unique_cell_edges(const Eigen::Matrix<int, Corners, Eigen::Dynamic>& cells) {
  std::vector<Edge> edges;
  edges.reserve(static_cast<std::size_t>(cells.cols()) * Corners * (Corners - 1) / 2);
  for (Eigen::Index c = 0; c < cells.cols(); ++c) {
    for (int i = 0; i < Corners; ++i) {
      for (int j = i + 1; j < Corners; ++j) {
        const int a = cells(i, c);
        const int b = cells(j, c);
        edges.emplace_back(std::min(a, b), std::max(a, b));
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return to_matrix(edges);
}

// A triangle with a repeated vertex is a segment or a point, not a piece of surface: it has no
// area, and counting its collapsed edges would make a sound surface look open or non-manifold.
bool collapsed(const Eigen::Matrix3Xi& triangles, Eigen::Index t) {
  const auto tri = triangles.col(t);
  return tri(0) == tri(1) || tri(1) == tri(2) || tri(2) == tri(0);
}

// Disjoint sets over vertex indices, for connected components.
class UnionFind {
 public:
  explicit UnionFind(int size) : parent_(static_cast<std::size_t>(size)) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int root(int v) {
    while (parent_[static_cast<std::size_t>(v)] != v) {
      // Path halving keeps the trees shallow without recursion.
      auto& p = parent_[static_cast<std::size_t>(v)];
      p = parent_[static_cast<std::size_t>(p)];
      v = p;
    }
    return v;
  }
  void unite(int a, int b) {
    const int ra = root(a);
    const int rb = root(b);
    parent_[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
  }

 private:
  std::vector<int> parent_;
};

void require_indices_in_range(const Eigen::Matrix3Xi& triangles, int num_vertices) {
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = triangles(k, t);
      if (v < 0 || v >= num_vertices) {
        throw std::out_of_range("surface_topology: triangle " + std::to_string(t)
                                + " has vertex index " + std::to_string(v) + " but there are "
                                + std::to_string(num_vertices) + " vertices");
      }
    }
  }
}

// One traversal of an undirected edge by a triangle; `forward` if it goes from lo to hi.
struct EdgeUse {
  int lo = 0;
  int hi = 0;
  bool forward = false;
  auto operator<=>(const EdgeUse&) const = default;
};

}  // namespace

Eigen::Matrix3Xi boundary_triangles(const Eigen::Matrix4Xi& tets) {
  // Each face once per tet using it, keyed by its sorted indices; a key seen once is boundary.
  struct FaceUse {
    Triangle key;
    Triangle outward;
  };
  std::vector<FaceUse> faces;
  faces.reserve(static_cast<std::size_t>(tets.cols()) * 4);
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    for (const auto& face : kOutwardFaces) {
      const Triangle outward{tets(face[0], t), tets(face[1], t), tets(face[2], t)};
      Triangle key = outward;
      std::sort(key.begin(), key.end());
      faces.push_back({key, outward});
    }
  }
  std::sort(faces.begin(), faces.end(),
            [](const FaceUse& a, const FaceUse& b) { return a.key < b.key; });

  std::vector<Triangle> boundary;
  for (std::size_t first = 0; first < faces.size();) {
    std::size_t end = first + 1;
    while (end < faces.size() && faces[end].key == faces[first].key) {
      ++end;
    }
    if (end - first == 1) {
      boundary.push_back(smallest_first(faces[first].outward));
    }
    first = end;
  }
  std::sort(boundary.begin(), boundary.end());
  return to_matrix(boundary);
}

TriMesh boundary_surface(const TetMesh& mesh, std::vector<int>* tet_vertex_of) {
  const Eigen::Matrix3Xi boundary = boundary_triangles(mesh.tets());

  // Surface vertices in increasing tet-mesh order; the renumbering is monotonic, so the sorted
  // order of boundary_triangles() carries over.
  std::vector<int> surface_index_of(static_cast<std::size_t>(mesh.num_vertices()), -1);
  for (Eigen::Index i = 0; i < boundary.size(); ++i) {
    surface_index_of[static_cast<std::size_t>(boundary.data()[i])] = 0;
  }
  std::vector<int> tet_vertex;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (surface_index_of[static_cast<std::size_t>(v)] == 0) {
      surface_index_of[static_cast<std::size_t>(v)] = static_cast<int>(tet_vertex.size());
      tet_vertex.push_back(v);
    }
  }

  TriMesh surface;
  surface.vertices.resize(3, static_cast<Eigen::Index>(tet_vertex.size()));
  for (std::size_t i = 0; i < tet_vertex.size(); ++i) {
    surface.vertices.col(static_cast<Eigen::Index>(i)) = mesh.rest_positions().col(tet_vertex[i]);
  }
  surface.triangles =
      boundary.unaryExpr([&](int v) { return surface_index_of[static_cast<std::size_t>(v)]; });
  if (tet_vertex_of != nullptr) {
    *tet_vertex_of = std::move(tet_vertex);
  }
  return surface;
}

Incidences group_by_owner(std::span<const int> owners, int num_owners) {
  Incidences result;
  result.offsets.assign(static_cast<std::size_t>(num_owners) + 1, 0);
  for (const int owner : owners) {
    ++result.offsets[static_cast<std::size_t>(owner) + 1];
  }
  for (std::size_t o = 1; o < result.offsets.size(); ++o) {
    result.offsets[o] += result.offsets[o - 1];
  }
  result.items.resize(owners.size());
  std::vector<int> fill(result.offsets.begin(), result.offsets.end() - 1);
  for (std::size_t k = 0; k < owners.size(); ++k) {
    result.items[static_cast<std::size_t>(fill[static_cast<std::size_t>(owners[k])]++)] =
        static_cast<int>(k);
  }
  return result;
}

Incidences vertex_corners(const Eigen::Matrix4Xi& tets, int num_vertices) {
  // Column-major: entry 4 t + a is corner a of tet t.
  return group_by_owner(std::span<const int>(tets.data(), static_cast<std::size_t>(tets.size())),
                        num_vertices);
}

Eigen::Matrix2Xi unique_edges(const Eigen::Matrix4Xi& tets) {
  return unique_cell_edges<4>(tets);
}

Eigen::Matrix2Xi unique_edges(const Eigen::Matrix3Xi& triangles) {
  return unique_cell_edges<3>(triangles);
}

int edge_index(const Eigen::Matrix2Xi& edges, int i, int j) {
  int lo = 0;
  int hi = static_cast<int>(edges.cols());
  while (lo < hi) {  // lexicographic: edges are sorted
    const int mid = (lo + hi) / 2;
    if (edges(0, mid) < i || (edges(0, mid) == i && edges(1, mid) < j)) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo;
}

SurfaceTopology surface_topology(const Eigen::Matrix3Xi& triangles, int num_vertices) {
  require_indices_in_range(triangles, num_vertices);

  SurfaceTopology topology;
  std::vector<EdgeUse> uses;
  uses.reserve(static_cast<std::size_t>(triangles.cols()) * 3);
  std::vector<bool> referenced(static_cast<std::size_t>(num_vertices), false);
  UnionFind components(num_vertices);
  int faces = 0;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    if (collapsed(triangles, t)) {
      continue;
    }
    ++faces;
    for (int k = 0; k < 3; ++k) {
      const int from = triangles(k, t);
      const int to = triangles((k + 1) % 3, t);
      uses.push_back({std::min(from, to), std::max(from, to), from < to});
      referenced[static_cast<std::size_t>(from)] = true;
      components.unite(from, to);
    }
  }

  std::sort(uses.begin(), uses.end());
  int edges = 0;
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t end = first + 1;
    while (end < uses.size() && uses[end].lo == uses[first].lo && uses[end].hi == uses[first].hi) {
      ++end;
    }
    ++edges;
    const std::size_t count = end - first;
    if (count == 1) {
      ++topology.boundary_edges;
    } else if (count >= 3) {
      ++topology.non_manifold_edges;
    } else if (uses[first].forward == uses[first + 1].forward) {
      // Two neighbours with matching orientation cross their shared edge in opposite directions.
      ++topology.misoriented_edges;
    }
    first = end;
  }

  int vertices = 0;
  for (int v = 0; v < num_vertices; ++v) {
    if (referenced[static_cast<std::size_t>(v)]) {
      ++vertices;
      if (components.root(v) == v) {
        ++topology.components;
      }
    }
  }
  topology.unreferenced_vertices = num_vertices - vertices;
  topology.euler_characteristic = vertices - edges + faces;
  return topology;
}

}  // namespace softbench
