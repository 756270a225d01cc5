// SPDX-License-Identifier: MIT
#include "geometry/marching_cubes_table.h"

#include <stdexcept>

// Generates the case table at compile time from the face rule described in the header. A broken
// invariant throws, which inside a constant expression is a compile error: if this file builds,
// every case chains into closed loops and has a valid triangulation.
namespace softbench::marching_cubes_table {
namespace {

constexpr int kNoEdge = -1;

constexpr int edge_between(int corner_a, int corner_b) {
  for (int e = 0; e < 12; ++e) {
    const CubeEdge& edge = kCubeEdges[e];
    if ((edge.corner0 == corner_a && edge.corner1 == corner_b)
        || (edge.corner0 == corner_b && edge.corner1 == corner_a)) {
      return e;
    }
  }
  throw std::logic_error("corners are not joined by a cube edge");
}

constexpr bool face_has_corner(int face, int corner) {
  for (int c : kCubeFaces[face]) {
    if (c == corner) {
      return true;
    }
  }
  return false;
}

/// Two distinct cube edges lie on a common face when all four of their corners do.
constexpr bool edges_share_face(int edge_a, int edge_b) {
  for (int f = 0; f < 6; ++f) {
    if (face_has_corner(f, kCubeEdges[edge_a].corner0)
        && face_has_corner(f, kCubeEdges[edge_a].corner1)
        && face_has_corner(f, kCubeEdges[edge_b].corner0)
        && face_has_corner(f, kCubeEdges[edge_b].corner1)) {
      return true;
    }
  }
  return false;
}

/// next[e] is the crossed edge that the face segment starting at crossed edge e leads to, or
/// kNoEdge for an uncrossed edge.
constexpr std::array<int, 12> chain_face_segments(int case_index) {
  auto inside = [case_index](int corner) { return ((case_index >> corner) & 1) != 0; };
  std::array<int, 12> next{};
  next.fill(kNoEdge);
  for (const auto& face : kCubeFaces) {
    for (int start = 0; start < 4; ++start) {
      // A run of inside corners starts at `start` when the walk enters the inside there.
      if (!inside(face[start]) || inside(face[(start + 3) % 4])) {
        continue;
      }
      int last = start;
      while (inside(face[(last + 1) % 4])) {
        last = (last + 1) % 4;
      }
      const int entry = edge_between(face[(start + 3) % 4], face[start]);
      const int exit = edge_between(face[last], face[(last + 1) % 4]);
      if (next[entry] != kNoEdge) {
        throw std::logic_error("a crossed edge starts two face segments");
      }
      next[entry] = exit;
    }
  }
  return next;
}

struct Loop {
  int size = 0;
  std::array<int, 12> edges{};
};

struct Loops {
  int count = 0;
  std::array<Loop, 4> loops{};  // each loop has at least three edges, so at most 12 / 3
};

constexpr Loops trace_loops(const std::array<int, 12>& next) {
  Loops result;
  std::array<bool, 12> visited{};
  for (int first = 0; first < 12; ++first) {
    if (next[first] == kNoEdge || visited[first]) {
      continue;
    }
    Loop loop;
    for (int e = first; !visited[e]; e = next[e]) {
      if (next[e] == kNoEdge) {
        throw std::logic_error("a face segment chain ends without closing");
      }
      visited[e] = true;
      loop.edges[loop.size++] = e;
    }
    if (loop.edges[0] != first || next[loop.edges[loop.size - 1]] != first || loop.size < 3) {
      throw std::logic_error("face segments do not form a simple closed loop");
    }
    result.loops[result.count++] = loop;
  }
  return result;
}

/// A fan from loop position `apex` is valid when none of its diagonals joins two edges of a
/// common face (those pairs are joined, if at all, only by the face's own segments).
constexpr bool fan_is_valid(const Loop& loop, int apex) {
  for (int step = 2; step <= loop.size - 2; ++step) {
    const int other = loop.edges[(apex + step) % loop.size];
    if (edges_share_face(loop.edges[apex], other)) {
      return false;
    }
  }
  return true;
}

constexpr void append_loop_triangles(const Loop& loop, CaseTriangles& out) {
  int apex = 0;
  while (apex < loop.size && !fan_is_valid(loop, apex)) {
    ++apex;
  }
  if (apex == loop.size) {
    throw std::logic_error("no fan of this loop avoids same-face diagonals");
  }
  for (int step = 1; step + 1 < loop.size; ++step) {
    if (out.count == kMaxTrianglesPerCase) {
      throw std::logic_error("case has more triangles than kMaxTrianglesPerCase");
    }
    out.triangles[out.count++] = {
        static_cast<std::uint8_t>(loop.edges[apex]),
        static_cast<std::uint8_t>(loop.edges[(apex + step) % loop.size]),
        static_cast<std::uint8_t>(loop.edges[(apex + step + 1) % loop.size])};
  }
}

constexpr std::array<CaseTriangles, 256> generate_case_table() {
  // The edge list must agree with the documented numbering: edge 4 * axis + r.
  for (int e = 0; e < 12; ++e) {
    const CubeEdge& edge = kCubeEdges[e];
    if (edge.axis != e / 4 || edge.corner1 != (edge.corner0 | (1 << edge.axis))
        || (edge.corner0 & (1 << edge.axis)) != 0
        || edge_between(edge.corner0, edge.corner1) != e) {
      throw std::logic_error("kCubeEdges breaks the documented numbering");
    }
  }
  std::array<CaseTriangles, 256> table{};
  for (int case_index = 0; case_index < 256; ++case_index) {
    const Loops loops = trace_loops(chain_face_segments(case_index));
    for (int l = 0; l < loops.count; ++l) {
      append_loop_triangles(loops.loops[l], table[case_index]);
    }
  }
  return table;
}

constexpr std::array<CaseTriangles, 256> kCaseTable = generate_case_table();

}  // namespace

const std::array<CaseTriangles, 256>& case_table() {
  return kCaseTable;
}

}  // namespace softbench::marching_cubes_table
