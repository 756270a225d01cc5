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
    // Equal parts, within a section of the box.
    for (int k = 0; k < parts; ++k) {
      const int size =
          cut.offsets[static_cast<std::size_t>(k) + 1] - cut.offsets[static_cast<std::size_t>(k)];
      EXPECT_NEAR(size, (mesh.num_vertices() - separator) / parts, 63) << "part " << k;
    }
    // Within a part the locality order is kept.
    for (int i = 1; i < cut.offsets[1]; ++i) {
      EXPECT_LT(cut.order.old_of_new[static_cast<std::size_t>(i) - 1],
                cut.order.old_of_new[static_cast<std::size_t>(i)]);
    }
  }
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
