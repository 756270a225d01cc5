// SPDX-License-Identifier: MIT
#include "geometry/vertex_order.h"

#include "geometry/mesh_data.h"
#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"

#include <algorithm>
#include <cstddef>
#include <numeric>

namespace softbench {

VertexOrder reverse_cuthill_mckee(const Eigen::Matrix4Xi& tets, int num_vertices) {
  const Eigen::Matrix2Xi edges = unique_edges(tets);
  // Adjacency lists, each sorted by degree (then index) once: the breadth-first pass then takes
  // a vertex's neighbours in that order.
  std::vector<int> owners;
  owners.reserve(2 * static_cast<std::size_t>(edges.cols()));
  std::vector<int> others;
  others.reserve(owners.capacity());
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    owners.push_back(edges(0, e));
    others.push_back(edges(1, e));
    owners.push_back(edges(1, e));
    others.push_back(edges(0, e));
  }
  const Incidences adjacency = group_by_owner(owners, num_vertices);
  std::vector<int> degree(static_cast<std::size_t>(num_vertices));
  for (int v = 0; v < num_vertices; ++v) {
    degree[static_cast<std::size_t>(v)] = adjacency.offsets[static_cast<std::size_t>(v) + 1]
                                          - adjacency.offsets[static_cast<std::size_t>(v)];
  }
  const auto fewer_neighbours = [&degree](int a, int b) {
    const int da = degree[static_cast<std::size_t>(a)];
    const int db = degree[static_cast<std::size_t>(b)];
    return da != db ? da < db : a < b;
  };
  std::vector<int> neighbours(adjacency.items.size());
  for (std::size_t k = 0; k < neighbours.size(); ++k) {
    neighbours[k] = others[static_cast<std::size_t>(adjacency.items[k])];
  }
  for (int v = 0; v < num_vertices; ++v) {
    std::sort(neighbours.begin() + adjacency.offsets[static_cast<std::size_t>(v)],
              neighbours.begin() + adjacency.offsets[static_cast<std::size_t>(v) + 1],
              fewer_neighbours);
  }

  std::vector<int> by_degree(static_cast<std::size_t>(num_vertices));
  std::iota(by_degree.begin(), by_degree.end(), 0);
  std::stable_sort(by_degree.begin(), by_degree.end(), fewer_neighbours);
  std::vector<char> numbered(static_cast<std::size_t>(num_vertices), 0);
  std::vector<int> sequence;  // Cuthill-McKee order: sequence[i] is the i-th vertex reached
  sequence.reserve(static_cast<std::size_t>(num_vertices));
  for (const int start : by_degree) {
    if (numbered[static_cast<std::size_t>(start)] != 0) {
      continue;
    }
    numbered[static_cast<std::size_t>(start)] = 1;
    sequence.push_back(start);
    for (std::size_t head = sequence.size() - 1; head < sequence.size(); ++head) {
      const auto v = static_cast<std::size_t>(sequence[head]);
      for (int k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k) {
        const int n = neighbours[static_cast<std::size_t>(k)];
        if (numbered[static_cast<std::size_t>(n)] == 0) {
          numbered[static_cast<std::size_t>(n)] = 1;
          sequence.push_back(n);
        }
      }
    }
  }

  VertexOrder order;
  order.old_of_new.assign(sequence.rbegin(), sequence.rend());
  order.new_of_old.resize(static_cast<std::size_t>(num_vertices));
  for (int i = 0; i < num_vertices; ++i) {
    order.new_of_old[static_cast<std::size_t>(order.old_of_new[static_cast<std::size_t>(i)])] = i;
  }
  return order;
}

TetMesh renumbered(const TetMesh& mesh, const VertexOrder& order) {
  MeshData data;
  data.source = "renumbered mesh";
  data.vertices.resize(3, mesh.num_vertices());
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    data.vertices.col(i) = mesh.rest_positions().col(order.old_of_new[static_cast<std::size_t>(i)]);
  }
  Eigen::Matrix4Xi tets(4, mesh.num_tets());
  std::vector<int> smallest(static_cast<std::size_t>(mesh.num_tets()));
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int a = 0; a < 4; ++a) {
      tets(a, t) = order.new_of_old[static_cast<std::size_t>(mesh.tets()(a, t))];
    }
    smallest[static_cast<std::size_t>(t)] = tets.col(t).minCoeff();
  }
  std::vector<int> tet_order(static_cast<std::size_t>(mesh.num_tets()));
  std::iota(tet_order.begin(), tet_order.end(), 0);
  std::stable_sort(tet_order.begin(), tet_order.end(), [&smallest](int a, int b) {
    return smallest[static_cast<std::size_t>(a)] < smallest[static_cast<std::size_t>(b)];
  });
  data.tetrahedra.resize(4, mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) {
    data.tetrahedra.col(t) = tets.col(tet_order[static_cast<std::size_t>(t)]);
  }
  return make_tet_mesh(data);
}

}  // namespace softbench
