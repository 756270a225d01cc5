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

PartitionedOrder partitioned(const Eigen::Matrix4Xi& tets, int num_vertices, int parts) {
  PartitionedOrder result;
  const auto n = static_cast<std::size_t>(num_vertices);
  if (parts <= 1 || num_vertices < 4 * parts) {
    result.order.new_of_old.resize(n);
    std::iota(result.order.new_of_old.begin(), result.order.new_of_old.end(), 0);
    result.order.old_of_new = result.order.new_of_old;
    result.offsets = {0, num_vertices, num_vertices};
    return result;
  }
  // Each vertex's lowest-numbered neighbour: a vertex is in the separator when that one lies
  // before the start of its own range.
  // And its work: the blocks of its row of a vertex-block matrix on the mesh, its neighbours
  // and itself, which a sweep or a product reads. A surface vertex has about half an interior
  // one's, so parts of equal vertex counts were not equal work (liver_x16: 25% more in the
  // second, which the first's thread then waited for at every sweep).
  std::vector<int> lowest(n);
  std::iota(lowest.begin(), lowest.end(), 0);
  std::vector<long long> work(n, 1);
  const Eigen::Matrix2Xi edges = unique_edges(tets);
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    const auto i = static_cast<std::size_t>(edges(0, e));
    const auto j = static_cast<std::size_t>(edges(1, e));
    lowest[i] = std::min(lowest[i], edges(1, e));
    lowest[j] = std::min(lowest[j], edges(0, e));
    ++work[i];
    ++work[j];
  }
  const auto count = static_cast<std::size_t>(parts);
  std::vector<int> cuts(count + 1);  // range k is [cuts[k], cuts[k + 1])
  for (std::size_t k = 0; k <= count; ++k) {
    cuts[k] =
        static_cast<int>(static_cast<long long>(num_vertices) * static_cast<long long>(k) / parts);
  }
  std::vector<char> separator(n, 0);
  const auto mark = [&] {
    for (std::size_t k = 1; k < count; ++k) {
      for (int v = cuts[k]; v < cuts[k + 1]; ++v) {
        separator[static_cast<std::size_t>(v)] = lowest[static_cast<std::size_t>(v)] < cuts[k];
      }
    }
    for (int v = 0; v < cuts[1]; ++v) {
      separator[static_cast<std::size_t>(v)] = 0;
    }
  };
  // Move each cut until the parts before it hold their share of the work outside the separator
  // (a few rounds: moving a cut moves its front, which is about as large). The cut moves over
  // as much work as the parts before it lack, counting every vertex it passes (a front moves
  // with its cut; skipping the current one's vertices would overshoot by a front).
  std::vector<long long> all_before(n + 1, 0);  // work before v
  for (std::size_t v = 0; v < n; ++v) {
    all_before[v + 1] = all_before[v] + work[v];
  }
  std::vector<long long> kept_before(n + 1, 0);  // work outside the separator before v
  for (int round = 0; round < 8; ++round) {
    mark();
    for (std::size_t v = 0; v < n; ++v) {
      kept_before[v + 1] = kept_before[v] + (separator[v] == 0 ? work[v] : 0);
    }
    for (std::size_t k = 1; k < count; ++k) {
      const auto at = static_cast<std::size_t>(cuts[k]);
      const long long wanted = kept_before[n] * static_cast<long long>(k) / parts;
      const long long target = all_before[at] + (wanted - kept_before[at]);
      const auto moved = static_cast<int>(
          std::lower_bound(all_before.begin(), all_before.end(), target) - all_before.begin());
      cuts[k] = std::clamp(moved, cuts[k - 1] + 1, num_vertices - 1);
    }
  }
  mark();
  result.offsets.push_back(0);
  result.order.old_of_new.reserve(n);
  for (std::size_t k = 0; k < count; ++k) {
    for (int v = cuts[k]; v < cuts[k + 1]; ++v) {
      if (separator[static_cast<std::size_t>(v)] == 0) {
        result.order.old_of_new.push_back(v);
      }
    }
    if (static_cast<int>(result.order.old_of_new.size()) == result.offsets.back()) {
      return partitioned(tets, num_vertices, 1);  // an empty part: too small a mesh to cut
    }
    result.offsets.push_back(static_cast<int>(result.order.old_of_new.size()));
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (separator[v] != 0) {
      result.order.old_of_new.push_back(static_cast<int>(v));
    }
  }
  result.offsets.push_back(num_vertices);
  result.order.new_of_old.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    result.order.new_of_old[static_cast<std::size_t>(result.order.old_of_new[i])] =
        static_cast<int>(i);
  }
  return result;
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
