// SPDX-License-Identifier: MIT
#include "geometry/marching_cubes.h"

#include "geometry/marching_cubes_table.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

// The grid walk of marching cubes (Lorensen & Cline 1987; the thesis's section 2.3). Cells are
// visited layer by layer in z; one output vertex is made per crossed grid edge, the first time a
// cell asks for it, so neighbouring cells share vertices and the output is an indexed mesh. The
// case table (marching_cubes_table.h) makes neighbouring cells agree on every shared face, so the
// triangles close up.
//
// Degenerate input: a sample exactly equal to the iso value is outside, so every crossed edge has
// two different values and the interpolation parameter t is well defined. t reaches 0 or 1 only
// at such a sample, putting the vertex exactly on it; the crossed edges meeting there (up to six)
// then give vertices at the same position, so some triangles have zero area. They are kept: the
// vertices stay distinct, so the mesh is still closed, manifold and oriented, and zero-area
// triangles add nothing to volume or area (smoothing pulls the vertices apart). Merging the
// coincident vertices could make edges shared by four triangles, and clamping t away from 0 and 1
// would move vertices off an iso-surface that is otherwise reproduced exactly.
namespace softbench {
namespace {

namespace table = marching_cubes_table;

constexpr int kNoVertex = -1;

void check_grid(const ScalarGrid& grid, float iso_value) {
  if ((grid.size.array() < 0).any()) {
    throw std::invalid_argument("marching_cubes: negative grid size");
  }
  const auto expected = static_cast<std::size_t>(grid.size.x())
                        * static_cast<std::size_t>(grid.size.y())
                        * static_cast<std::size_t>(grid.size.z());
  if (grid.values.size() != expected) {
    throw std::invalid_argument("marching_cubes: grid has " + std::to_string(grid.values.size())
                                + " values, size says " + std::to_string(expected));
  }
  // A zero or negative spacing would fold or mirror the output and turn its orientation inward.
  if (!(grid.spacing.array() > 0.0).all() || !grid.spacing.allFinite()
      || !grid.origin.allFinite()) {
    throw std::invalid_argument("marching_cubes: spacing must be positive and finite");
  }
  if (!std::isfinite(iso_value)) {
    throw std::invalid_argument("marching_cubes: iso value must be finite");
  }
  if (!std::all_of(grid.values.begin(), grid.values.end(),
                   [](float v) { return std::isfinite(v); })) {
    throw std::invalid_argument("marching_cubes: grid has a non-finite sample");
  }
}

/// The field's gradient at a sample (thesis eq. 2-2): central differences inside the grid,
/// one-sided differences on its border, divided by the spacing so that it is per metre.
Eigen::Vector3d sample_gradient(const ScalarGrid& grid, int i, int j, int k) {
  const std::array<int, 3> at = {i, j, k};
  Eigen::Vector3d gradient;
  for (int axis = 0; axis < 3; ++axis) {
    std::array<int, 3> below = at;
    std::array<int, 3> above = at;
    below[axis] = std::max(at[axis] - 1, 0);
    above[axis] = std::min(at[axis] + 1, grid.size[axis] - 1);
    const double rise = static_cast<double>(grid.at(above[0], above[1], above[2]))
                        - static_cast<double>(grid.at(below[0], below[1], below[2]));
    gradient[axis] = rise / (static_cast<double>(above[axis] - below[axis]) * grid.spacing[axis]);
  }
  return gradient;
}

/// Output vertex ids of the grid edges touched by one layer of cells (between sample planes k and
/// k + 1): the x and y edges of both planes and the z edges between them. Two planes of ids
/// instead of one per grid edge keep memory at O(nx * ny).
class LayerEdgeVertices {
 public:
  LayerEdgeVertices(int nx, int ny)
      : nx_(static_cast<std::size_t>(nx)),
        plane_size_(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny)),
        lower_plane_(2 * plane_size_, kNoVertex),
        upper_plane_(2 * plane_size_, kNoVertex),
        vertical_(plane_size_, kNoVertex) {}

  /// Moves to the next layer of cells: its lower plane is the previous layer's upper plane.
  void next_layer() {
    std::swap(lower_plane_, upper_plane_);
    std::fill(upper_plane_.begin(), upper_plane_.end(), kNoVertex);
    std::fill(vertical_.begin(), vertical_.end(), kNoVertex);
  }

  /// The vertex id slot of the grid edge leaving sample (i, j, layer + dk) along `axis`
  /// (dk is 0 for z edges).
  int& slot(int i, int j, int dk, int axis) {
    const std::size_t in_plane = static_cast<std::size_t>(i) + nx_ * static_cast<std::size_t>(j);
    if (axis == 2) {
      return vertical_[in_plane];
    }
    std::vector<int>& plane = dk == 0 ? lower_plane_ : upper_plane_;
    return plane[2 * in_plane + static_cast<std::size_t>(axis)];
  }

 private:
  std::size_t nx_;
  std::size_t plane_size_;
  std::vector<int> lower_plane_;  // x and y edges of sample plane k, interleaved
  std::vector<int> upper_plane_;  // x and y edges of sample plane k + 1
  std::vector<int> vertical_;     // z edges from plane k to k + 1
};

/// Collects vertices (with unnormalised outward normals, if wanted) and triangles.
class SurfaceBuilder {
 public:
  SurfaceBuilder(const ScalarGrid& grid, float iso_value, bool with_normals)
      : grid_(grid), iso_(iso_value), with_normals_(with_normals) {}

  /// The id of the vertex on cube edge `edge` of cell (i, j, k), made on first request.
  /// `corner_values` are the cell's samples in corner order.
  int vertex_on(int edge,
                int i,
                int j,
                int k,
                const std::array<float, 8>& corner_values,
                LayerEdgeVertices& layer_vertices) {
    const table::CubeEdge& cube_edge = table::kCubeEdges[edge];
    const table::CornerOffset offset = table::corner_offset(cube_edge.corner0);
    const int si = i + offset.x;
    const int sj = j + offset.y;
    const int sk = k + offset.z;
    int& id = layer_vertices.slot(si, sj, offset.z, cube_edge.axis);
    if (id != kNoVertex) {
      return id;
    }
    // Thesis eq. 2-3: the iso-point by linear interpolation between the edge's samples. The two
    // values differ (one is > iso, the other <= iso), so t is well defined and in [0, 1].
    const double value0 = corner_values[cube_edge.corner0];
    const double value1 = corner_values[cube_edge.corner1];
    const double t = (static_cast<double>(iso_) - value0) / (value1 - value0);

    // Only the edge's own coordinate is interpolated, so vertices on one grid line stay exactly
    // on it, and t = 0 gives the sample position exactly.
    Eigen::Vector3d position = grid_.position(si, sj, sk);
    const int axis = cube_edge.axis;
    const int start_index = Eigen::Vector3i(si, sj, sk)[axis];
    position[axis] = grid_.origin[axis] + (start_index + t) * grid_.spacing[axis];
    positions_.insert(positions_.end(), position.data(), position.data() + 3);

    if (with_normals_) {
      // Thesis eq. 2-2 interpolated like the position; inside is high, so outward is -gradient.
      const Eigen::Vector3d gradient0 = sample_gradient(grid_, si, sj, sk);
      const Eigen::Vector3d gradient1 = sample_gradient(
          grid_, si + (axis == 0 ? 1 : 0), sj + (axis == 1 ? 1 : 0), sk + (axis == 2 ? 1 : 0));
      const Eigen::Vector3d outward = -((1.0 - t) * gradient0 + t * gradient1);
      normals_.insert(normals_.end(), outward.data(), outward.data() + 3);
    }
    id = vertex_count_++;
    return id;
  }

  void add_triangle(int a, int b, int c) { triangles_.insert(triangles_.end(), {a, b, c}); }

  TriMesh mesh() const {
    TriMesh mesh;
    mesh.vertices = Eigen::Map<const Eigen::Matrix3Xd>(positions_.data(), 3, vertex_count_);
    mesh.triangles = Eigen::Map<const Eigen::Matrix3Xi>(
        triangles_.data(), 3, static_cast<Eigen::Index>(triangles_.size() / 3));
    return mesh;
  }

  /// Unit outward normals. Where the interpolated gradient vanishes (a flat field around the
  /// edge), the area-weighted normal of the surrounding triangles stands in; a vertex whose
  /// triangles all have zero area as well gets a zero normal.
  Eigen::Matrix3Xd unit_normals(const TriMesh& mesh) const {
    Eigen::Matrix3Xd normals =
        Eigen::Map<const Eigen::Matrix3Xd>(normals_.data(), 3, vertex_count_);
    std::vector<bool> from_triangles(static_cast<std::size_t>(vertex_count_), false);
    bool any_from_triangles = false;
    for (int v = 0; v < vertex_count_; ++v) {
      const double length = normals.col(v).norm();
      if (length > 0.0 && std::isfinite(length)) {
        normals.col(v) /= length;
      } else {
        normals.col(v).setZero();
        from_triangles[static_cast<std::size_t>(v)] = true;
        any_from_triangles = true;
      }
    }
    if (!any_from_triangles) {
      return normals;
    }
    for (int t = 0; t < mesh.num_triangles(); ++t) {
      const auto corners = mesh.triangles.col(t);
      const Eigen::Vector3d x0 = mesh.vertices.col(corners(0));
      const Eigen::Vector3d area_normal =
          (mesh.vertices.col(corners(1)) - x0).cross(mesh.vertices.col(corners(2)) - x0);
      for (int corner = 0; corner < 3; ++corner) {
        if (from_triangles[static_cast<std::size_t>(corners(corner))]) {
          normals.col(corners(corner)) += area_normal;
        }
      }
    }
    for (int v = 0; v < vertex_count_; ++v) {
      if (from_triangles[static_cast<std::size_t>(v)]) {
        normals.col(v).normalize();  // Eigen leaves a zero vector unchanged
      }
    }
    return normals;
  }

 private:
  const ScalarGrid& grid_;
  float iso_;
  bool with_normals_;
  int vertex_count_ = 0;
  std::vector<double> positions_;  // 3 per vertex
  std::vector<double> normals_;    // 3 per vertex, unnormalised
  std::vector<int> triangles_;     // 3 per triangle
};

}  // namespace

TriMesh marching_cubes(const ScalarGrid& grid, float iso_value, Eigen::Matrix3Xd* normals) {
  check_grid(grid, iso_value);
  SurfaceBuilder builder(grid, iso_value, normals != nullptr);
  const int nx = grid.size.x();
  const int ny = grid.size.y();
  const int nz = grid.size.z();
  if (nx >= 2 && ny >= 2 && nz >= 2) {
    // Index distance from a cell's corner 0 to each of its corners (corner bits: x, y, z).
    const std::size_t row = static_cast<std::size_t>(nx);
    const std::size_t plane = row * static_cast<std::size_t>(ny);
    std::array<std::size_t, 8> corner_stride{};
    for (int c = 0; c < 8; ++c) {
      const table::CornerOffset offset = table::corner_offset(c);
      corner_stride[static_cast<std::size_t>(c)] = static_cast<std::size_t>(offset.x)
                                                   + row * static_cast<std::size_t>(offset.y)
                                                   + plane * static_cast<std::size_t>(offset.z);
    }
    const auto& cases = table::case_table();
    LayerEdgeVertices layer_vertices(nx, ny);
    std::array<float, 8> corner_values{};
    std::array<int, 3> triangle{};
    for (int k = 0; k + 1 < nz; ++k) {
      layer_vertices.next_layer();
      for (int j = 0; j + 1 < ny; ++j) {
        for (int i = 0; i + 1 < nx; ++i) {
          const std::size_t base = grid.index(i, j, k);
          unsigned case_index = 0;
          for (std::size_t c = 0; c < 8; ++c) {
            corner_values[c] = grid.values[base + corner_stride[c]];
            case_index |= static_cast<unsigned>(corner_values[c] > iso_value) << c;
          }
          const table::CaseTriangles& case_triangles = cases[case_index];
          for (int t = 0; t < case_triangles.count; ++t) {
            for (std::size_t corner = 0; corner < 3; ++corner) {
              triangle[corner] =
                  builder.vertex_on(case_triangles.triangles[static_cast<std::size_t>(t)][corner],
                                    i, j, k, corner_values, layer_vertices);
            }
            builder.add_triangle(triangle[0], triangle[1], triangle[2]);
          }
        }
      }
    }
  }
  TriMesh mesh = builder.mesh();
  if (normals != nullptr) {
    *normals = builder.unit_normals(mesh);
  }
  return mesh;
}

}  // namespace softbench
