// SPDX-License-Identifier: MIT
#include "geometry/vertex_order.h"

#include "geometry/mesh_data.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <numeric>
#include <random>
#include <vector>

namespace softbench {
namespace {

/// The largest |i - j| over the mesh's edges: how far apart in memory a vertex's neighbours lie.
int bandwidth(const Eigen::Matrix4Xi& tets, const std::vector<int>& new_of_old) {
  const Eigen::Matrix2Xi edges = unique_edges(tets);
  int widest = 0;
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    widest = std::max(widest, std::abs(new_of_old[static_cast<std::size_t>(edges(0, e))]
                                       - new_of_old[static_cast<std::size_t>(edges(1, e))]));
  }
  return widest;
}

std::vector<int> identity(int count) {
  std::vector<int> order(static_cast<std::size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  return order;
}

/// A sweep's work at each vertex: the blocks of its row, its neighbours and itself.
std::vector<long long> vertex_work(const TetMesh& mesh) {
  std::vector<long long> work(static_cast<std::size_t>(mesh.num_vertices()), 1);
  const Eigen::Matrix2Xi edges = unique_edges(mesh.tets());
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    ++work[static_cast<std::size_t>(edges(0, e))];
    ++work[static_cast<std::size_t>(edges(1, e))];
  }
  return work;
}

/// The work of the vertices of cut's range k (vertex_work()).
long long range_work(const PartitionedOrder& cut, const std::vector<long long>& work, int k) {
  long long sum = 0;
  for (int i = cut.offsets[static_cast<std::size_t>(k)];
       i < cut.offsets[static_cast<std::size_t>(k) + 1]; ++i) {
    sum += work[static_cast<std::size_t>(cut.order.old_of_new[static_cast<std::size_t>(i)])];
  }
  return sum;
}

/// A box's tets with its vertices numbered at random.
MeshData shuffled_box(int nx, int ny, int nz) {
  MeshData box = test::box_tets(nx, ny, nz, 0.3, 0.2, 0.1);
  std::vector<int> new_of_old = identity(static_cast<int>(box.vertices.cols()));
  std::mt19937 random(7);
  std::shuffle(new_of_old.begin(), new_of_old.end(), random);
  MeshData shuffled = box;
  for (Eigen::Index v = 0; v < box.vertices.cols(); ++v) {
    shuffled.vertices.col(new_of_old[static_cast<std::size_t>(v)]) = box.vertices.col(v);
  }
  for (Eigen::Index t = 0; t < box.tetrahedra.cols(); ++t) {
    for (int a = 0; a < 4; ++a) {
      shuffled.tetrahedra(a, t) = new_of_old[static_cast<std::size_t>(box.tetrahedra(a, t))];
    }
  }
  return shuffled;
}

TEST(ReverseCuthillMcKee, NumbersABoxShuffledAtRandomWithinItsLayersBandwidth) {
  // 12 x 6 x 4 cells: 13 * 7 * 5 = 455 vertices. Numbered layer by layer across the box's
  // smallest section, an edge spans at most about one layer (7 * 5 + 7 + 1 = 43 vertices); at
  // random, nearly the whole mesh.
  const TetMesh mesh = make_tet_mesh(shuffled_box(12, 6, 4));
  const VertexOrder order = reverse_cuthill_mckee(mesh.tets(), mesh.num_vertices());
  ASSERT_EQ(order.new_of_old.size(), static_cast<std::size_t>(mesh.num_vertices()));
  std::vector<int> sorted = order.new_of_old;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, identity(mesh.num_vertices()));  // a permutation
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    EXPECT_EQ(
        order.old_of_new[static_cast<std::size_t>(order.new_of_old[static_cast<std::size_t>(v)])],
        v);
  }
  const int before = bandwidth(mesh.tets(), identity(mesh.num_vertices()));
  const int after = bandwidth(mesh.tets(), order.new_of_old);
  EXPECT_GT(before, 300);
  EXPECT_LE(after, 2 * 43);
}

TEST(ReverseCuthillMcKee, NumbersEveryPartOfADisconnectedMesh) {
  // Two tets far apart and sharing nothing.
  MeshData two = test::single_tet();
  two.vertices.conservativeResize(3, 8);
  two.vertices.rightCols<4>() = two.vertices.leftCols<4>().colwise() + Eigen::Vector3d(5, 0, 0);
  two.tetrahedra.conservativeResize(4, 2);
  two.tetrahedra.col(1) = two.tetrahedra.col(0).array() + 4;
  const TetMesh mesh = make_tet_mesh(two);
  const VertexOrder order = reverse_cuthill_mckee(mesh.tets(), mesh.num_vertices());
  std::vector<int> sorted = order.new_of_old;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, identity(8));
}

TEST(Renumbered, IsTheSameBodyWithItsTetsInOrderOfTheirFirstVertex) {
  const TetMesh mesh = make_tet_mesh(shuffled_box(6, 3, 2));
  const VertexOrder order = reverse_cuthill_mckee(mesh.tets(), mesh.num_vertices());
  const TetMesh inner = renumbered(mesh, order);
  ASSERT_EQ(inner.num_vertices(), mesh.num_vertices());
  ASSERT_EQ(inner.num_tets(), mesh.num_tets());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    EXPECT_EQ(inner.rest_positions().col(order.new_of_old[static_cast<std::size_t>(v)]),
              mesh.rest_positions().col(v));
  }
  EXPECT_NEAR(mesh_volume(inner), mesh_volume(mesh), test::kRoundoff * mesh_volume(mesh));
  // The same tets, each with its corners in its own order (so still positive), sorted.
  std::vector<std::array<int, 4>> expected;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    std::array<int, 4> tet{};
    for (int a = 0; a < 4; ++a) {
      tet[static_cast<std::size_t>(a)] =
          order.new_of_old[static_cast<std::size_t>(mesh.tets()(a, t))];
    }
    expected.push_back(tet);
  }
  std::vector<std::array<int, 4>> got;
  int previous_first = -1;
  for (int t = 0; t < inner.num_tets(); ++t) {
    got.push_back({inner.tets()(0, t), inner.tets()(1, t), inner.tets()(2, t), inner.tets()(3, t)});
    const int first = inner.tets().col(t).minCoeff();
    EXPECT_GE(first, previous_first);
    previous_first = first;
  }
  std::sort(expected.begin(), expected.end());
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, expected);
}

/// The part (0 .. parts - 1) or the separator (parts) of new vertex i.
int range_of(const std::vector<int>& offsets, int i) {
  return static_cast<int>(std::upper_bound(offsets.begin(), offsets.end(), i) - offsets.begin())
         - 1;
}

TEST(Partitioned, LeavesNoEdgeBetweenTwoPartsAndKeepsTheSeparatorToACut) {
  // 30 x 8 x 6 cells, numbered by reverse Cuthill-McKee: 31 * 9 * 7 = 1953 vertices. A cut of
  // the breadth-first numbering crosses the box; its front is about one level of the search,
  // the box's section (63 vertices) give or take the diagonal of the levels.
  const TetMesh box = make_tet_mesh(shuffled_box(30, 8, 6));
  const TetMesh mesh = renumbered(box, reverse_cuthill_mckee(box.tets(), box.num_vertices()));
  const Eigen::Matrix2Xi edges = unique_edges(mesh.tets());
  for (const int parts : {2, 3, 4}) {
    const PartitionedOrder cut = partitioned(mesh.tets(), mesh.num_vertices(), parts);
    ASSERT_EQ(cut.offsets.size(), static_cast<std::size_t>(parts) + 2);
    EXPECT_EQ(cut.offsets.front(), 0);
    EXPECT_EQ(cut.offsets.back(), mesh.num_vertices());
    std::vector<int> sorted = cut.order.new_of_old;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, identity(mesh.num_vertices()));  // a permutation
    for (int i = 0; i < mesh.num_vertices(); ++i) {
      EXPECT_EQ(cut.order.new_of_old[static_cast<std::size_t>(
                    cut.order.old_of_new[static_cast<std::size_t>(i)])],
                i);
    }
    // No edge joins two parts: a sweep over one never reads another's values.
    int crossing = 0;
    for (Eigen::Index e = 0; e < edges.cols(); ++e) {
      const int a =
          range_of(cut.offsets, cut.order.new_of_old[static_cast<std::size_t>(edges(0, e))]);
      const int b =
          range_of(cut.offsets, cut.order.new_of_old[static_cast<std::size_t>(edges(1, e))]);
      crossing += a != b && a < parts && b < parts ? 1 : 0;
    }
    EXPECT_EQ(crossing, 0) << parts << " parts";
    // The separator: one front a cut, each within three sections of the box.
    const int separator = cut.offsets[static_cast<std::size_t>(parts) + 1]
                          - cut.offsets[static_cast<std::size_t>(parts)];
    EXPECT_GT(separator, 0);
    EXPECT_LE(separator, (parts - 1) * 3 * 63) << parts << " parts";
    // Parts of equal work, within a section of the box's (63 vertices at the mean work; the
    // end faces' vertices have fewer neighbours, so the end parts hold a few more vertices).
    const std::vector<long long> work = vertex_work(mesh);
    long long kept = 0;
    for (int k = 0; k < parts; ++k) {
      kept += range_work(cut, work, k);
    }
    const double section = 63.0
                           * static_cast<double>(std::accumulate(work.begin(), work.end(), 0LL))
                           / mesh.num_vertices();
    for (int k = 0; k < parts; ++k) {
      EXPECT_NEAR(static_cast<double>(range_work(cut, work, k)), static_cast<double>(kept) / parts,
                  section)
          << "part " << k;
    }
    // Within a part the locality order is kept.
    for (int i = 1; i < cut.offsets[1]; ++i) {
      EXPECT_LT(cut.order.old_of_new[static_cast<std::size_t>(i) - 1],
                cut.order.old_of_new[static_cast<std::size_t>(i)]);
    }
  }
}

/// A 30 x 6 x 6-cell box whose far half is cut down to its bottom layer of cells: a thick half
/// and a thin one, with the unused vertices dropped. The thin half's vertices all lie on the
/// surface, with fewer neighbours than the thick half's interior ones.
MeshData thick_and_thin_box() {
  const MeshData box = test::box_tets(30, 6, 6, 0.3, 0.06, 0.06);
  std::vector<int> kept_tets;
  for (Eigen::Index t = 0; t < box.tetrahedra.cols(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) {
      centroid += box.vertices.col(box.tetrahedra(a, t)) / 4.0;
    }
    if (centroid.x() < 0.15 || centroid.z() < 0.01) {
      kept_tets.push_back(static_cast<int>(t));
    }
  }
  std::vector<int> new_of_old(static_cast<std::size_t>(box.vertices.cols()), -1);
  MeshData result;
  result.tetrahedra.resize(4, static_cast<Eigen::Index>(kept_tets.size()));
  int used = 0;
  for (std::size_t k = 0; k < kept_tets.size(); ++k) {
    for (int a = 0; a < 4; ++a) {
      int& index = new_of_old[static_cast<std::size_t>(box.tetrahedra(a, kept_tets[k]))];
      if (index < 0) {
        index = used++;
      }
      result.tetrahedra(a, static_cast<Eigen::Index>(k)) = index;
    }
  }
  result.vertices.resize(3, used);
  for (std::size_t v = 0; v < new_of_old.size(); ++v) {
    if (new_of_old[v] >= 0) {
      result.vertices.col(new_of_old[v]) = box.vertices.col(static_cast<Eigen::Index>(v));
    }
  }
  return result;
}

TEST(Partitioned, GivesThePartsEqualWorkWhereTheirVerticesDifferInDegree) {
  // A sweep's work at a vertex is the blocks of its row: its neighbours and itself. Parts of
  // equal vertex counts (472 and 473) differ by 8% in work here (the cut lies in the thick
  // half, and the part holding the thin half has the vertices with fewer neighbours); parts of
  // equal work are within 0.3% of each other (5,603 and 5,585), their counts 454 and 490.
  // Bounds: 1% and 20 vertices.
  const TetMesh shape = make_tet_mesh(thick_and_thin_box());
  const TetMesh mesh = renumbered(shape, reverse_cuthill_mckee(shape.tets(), shape.num_vertices()));
  const std::vector<long long> work = vertex_work(mesh);
  const PartitionedOrder cut = partitioned(mesh.tets(), mesh.num_vertices(), 2);
  ASSERT_EQ(cut.offsets.size(), 4U);
  std::array<long long, 2> part_work{};
  std::array<int, 2> part_vertices{};
  for (int k = 0; k < 2; ++k) {
    part_work[static_cast<std::size_t>(k)] = range_work(cut, work, k);
    part_vertices[static_cast<std::size_t>(k)] =
        cut.offsets[static_cast<std::size_t>(k) + 1] - cut.offsets[static_cast<std::size_t>(k)];
  }
  const auto larger = static_cast<double>(std::max(part_work[0], part_work[1]));
  EXPECT_LT(std::abs(static_cast<double>(part_work[0] - part_work[1])) / larger, 0.01)
      << part_work[0] << " against " << part_work[1];
  // And so the vertex counts differ: the work, not the count, was balanced.
  EXPECT_GT(std::abs(part_vertices[0] - part_vertices[1]), 20)
      << part_vertices[0] << " against " << part_vertices[1];
}

TEST(Partitioned, KeepsASmallMeshOrOnePartWhole) {
  const TetMesh mesh = make_tet_mesh(test::single_tet());
  for (const int parts : {1, 2}) {
    const PartitionedOrder cut = partitioned(mesh.tets(), mesh.num_vertices(), parts);
    EXPECT_EQ(cut.offsets, (std::vector<int>{0, 4, 4}));
    EXPECT_EQ(cut.order.new_of_old, identity(4));
  }
}

}  // namespace
}  // namespace softbench
