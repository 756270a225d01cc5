// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstdint>

// The marching-cubes case table (Lorensen & Cline 1987), generated at compile time from a rule
// instead of typed in, so that neighbouring cells always agree and the surface is closed.
//
// Numbering conventions (all used by marching_cubes.cpp and the tests):
//
//   Corner c (0..7) of a cell sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1) from the cell's
//   minimum corner: bit 0 is x, bit 1 is y, bit 2 is z.
//
//          6 ---------- 7            Edges are grouped by axis: 0..3 run along x, 4..7 along y,
//         /|           /|            8..11 along z. Within a group, edge 4 * axis + r joins the
//        / |          / |            two corners whose coordinates on the other two axes are
//       4 ---------- 5  |            the bits of r, lower axis first:
//       |  2 --------|- 3              x edges: 0 = (0,1)  1 = (2,3)  2 = (4,5)  3 = (6,7)
//       | /          | /               y edges: 4 = (0,2)  5 = (1,3)  6 = (4,6)  7 = (5,7)
//       |/           |/                z edges: 8 = (0,4)  9 = (1,5) 10 = (2,6) 11 = (3,7)
//       0 ---------- 1   -> x  (y into the page, z up)
//
//   An edge's first corner is the one nearer the cell's minimum corner.
//
//   Faces (0..5) are -x, +x, -y, +y, -z, +z; each lists its corners counter-clockwise as seen
//   from outside the cube.
//
//   Case index: bit c is set when corner c is inside (sample strictly greater than the iso value).
//
// The rule. On each face, every maximal run of consecutive inside corners (walking the face
// counter-clockwise from outside) is cut off by one segment, from the crossed edge where the walk
// enters the run to the crossed edge where it leaves it. On an ambiguous face (two diagonally
// opposite inside corners) that cuts off each inside corner separately: inside corners separated,
// outside corners connected. The choice depends only on the face's own corners, so the two cells
// sharing a face make the same one. Each crossed cube edge lies on two faces, being entered on one
// and left on the other, so the segments chain into closed loops; each loop walks with the inside
// on its right as seen from outside the cube, which makes its triangles face from inside (high
// values) to outside (low values). Each loop of n edges is triangulated into n - 2 triangles
// without a diagonal between two edges of a common face (such a diagonal could coincide with one
// in the neighbouring cell and make a non-manifold edge).
namespace softbench::marching_cubes_table {

/// A cell corner's offset from the cell's minimum corner, one of {0, 1} per axis.
struct CornerOffset {
  int x, y, z;
};
inline constexpr CornerOffset corner_offset(int corner) {
  return {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
}

/// A cube edge: its two corners (corner0 nearer the minimum corner) and the axis it runs along.
struct CubeEdge {
  int corner0, corner1, axis;
};
inline constexpr std::array<CubeEdge, 12> kCubeEdges = {{
    {0, 1, 0},
    {2, 3, 0},
    {4, 5, 0},
    {6, 7, 0},  // along x
    {0, 2, 1},
    {1, 3, 1},
    {4, 6, 1},
    {5, 7, 1},  // along y
    {0, 4, 2},
    {1, 5, 2},
    {2, 6, 2},
    {3, 7, 2},  // along z
}};

/// The six faces -x, +x, -y, +y, -z, +z, corners counter-clockwise as seen from outside.
inline constexpr std::array<std::array<int, 4>, 6> kCubeFaces = {{
    {0, 4, 6, 2},  // -x
    {1, 3, 7, 5},  // +x
    {0, 1, 5, 4},  // -y
    {2, 6, 7, 3},  // +y
    {0, 2, 3, 1},  // -z
    {4, 5, 7, 6},  // +z
}};

/// The most triangles any case has (the generator fails to compile if a case needed more).
inline constexpr int kMaxTrianglesPerCase = 5;

/// One case's triangles, each three cube-edge indices (0..11) ordered counter-clockwise as seen
/// from outside (from the low-valued side).
struct CaseTriangles {
  int count = 0;
  std::array<std::array<std::uint8_t, 3>, kMaxTrianglesPerCase> triangles{};
};

/// The 256 cases, indexed by the case index described above.
const std::array<CaseTriangles, 256>& case_table();

}  // namespace softbench::marching_cubes_table
