// SPDX-License-Identifier: MIT
#include "geometry/vtk_cells.h"

#include "geometry/text_tokenizer.h"

namespace softbench {
namespace {

// VTK's cell type numbers run from 0 (empty cell) to 81 (Bezier wedge); beyond is not VTK.
constexpr std::int64_t kLargestVtkCellType = 81;

// The vertices of `cell` as mesh indices, or the problem with the first one out of range.
std::optional<std::string> cell_vertices(const VtkCellArray& cells,
                                         std::size_t cell,
                                         int vertex_count,
                                         std::vector<int>& vertices) {
  vertices.clear();
  for (auto k = cells.offsets[cell]; k < cells.offsets[cell + 1]; ++k) {
    const std::int64_t index = cells.connectivity[static_cast<std::size_t>(k)];
    if (index < 0 || index >= vertex_count) {
      return concat("cell ", cell, ": point index ", index, " out of range (file has ",
                    vertex_count, " points)");
    }
    vertices.push_back(static_cast<int>(index));
  }
  return std::nullopt;
}

std::string point_count_problem(std::size_t cell, std::size_t points, const char* needs) {
  return concat("cell ", cell, " has ", points, " points; ", needs);
}

}  // namespace

std::optional<std::string> cells_from_legacy(std::span<const std::int64_t> legacy,
                                             std::size_t cell_count,
                                             VtkCellArray& cells) {
  cells = VtkCellArray{};
  std::size_t position = 0;
  while (position < legacy.size()) {
    const std::int64_t points = legacy[position];
    if (points < 0 || static_cast<std::uint64_t>(points) > legacy.size() - position - 1) {
      return concat("cell ", cells.size(), " claims ", points, " points, more than the ",
                    legacy.size() - position - 1, " values left in the cell list");
    }
    cells.connectivity.insert(cells.connectivity.end(),
                              legacy.begin() + static_cast<std::ptrdiff_t>(position + 1),
                              legacy.begin() + static_cast<std::ptrdiff_t>(position + 1)
                                  + static_cast<std::ptrdiff_t>(points));
    cells.offsets.push_back(static_cast<std::int64_t>(cells.connectivity.size()));
    position += 1 + static_cast<std::size_t>(points);
  }
  if (cells.size() != cell_count) {
    return concat("header says ", cell_count, " cells, the cell list holds ", cells.size());
  }
  return std::nullopt;
}

std::optional<std::string> check_offsets(const VtkCellArray& cells) {
  if (cells.offsets.empty() || cells.offsets.front() != 0) {
    return "offsets must start at 0";
  }
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (cells.offsets[c + 1] < cells.offsets[c]) {
      return concat("offsets decrease at cell ", c, " (", cells.offsets[c], " then ",
                    cells.offsets[c + 1], ")");
    }
  }
  if (cells.offsets.back() != static_cast<std::int64_t>(cells.connectivity.size())) {
    return concat("offsets end at ", cells.offsets.back(), " but connectivity has ",
                  cells.connectivity.size(), " entries");
  }
  return std::nullopt;
}

std::optional<std::string> append_cells_by_type(const VtkCellArray& cells,
                                                std::span<const std::int64_t> types,
                                                MeshBuilder& mesh) {
  if (types.size() != cells.size()) {
    return concat(cells.size(), " cells but ", types.size(), " cell types");
  }
  std::vector<int> vertices;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (types[c] < 0 || types[c] > kLargestVtkCellType) {
      return concat("cell ", c, " has unknown cell type ", types[c]);
    }
    if (types[c] != kVtkTriangle && types[c] != kVtkTetra) {
      continue;
    }
    if (auto problem = cell_vertices(cells, c, mesh.vertex_count(), vertices)) {
      return problem;
    }
    if (types[c] == kVtkTriangle) {
      if (vertices.size() != 3) {
        return point_count_problem(c, vertices.size(), "type 5 (triangle) needs 3");
      }
      mesh.add_triangle(vertices[0], vertices[1], vertices[2]);
    } else {
      if (vertices.size() != 4) {
        return point_count_problem(c, vertices.size(), "type 10 (tetra) needs 4");
      }
      mesh.add_tetrahedron(vertices[0], vertices[1], vertices[2], vertices[3]);
    }
  }
  return std::nullopt;
}

std::optional<std::string> append_polygons(const VtkCellArray& cells, MeshBuilder& mesh) {
  std::vector<int> vertices;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (auto problem = cell_vertices(cells, c, mesh.vertex_count(), vertices)) {
      return problem;
    }
    if (vertices.size() < 3) {
      return point_count_problem(c, vertices.size(), "a polygon needs at least 3");
    }
    for (std::size_t i = 1; i + 1 < vertices.size(); ++i) {
      mesh.add_triangle(vertices[0], vertices[i], vertices[i + 1]);
    }
  }
  return std::nullopt;
}

std::optional<std::string> append_triangle_strips(const VtkCellArray& cells, MeshBuilder& mesh) {
  std::vector<int> vertices;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (auto problem = cell_vertices(cells, c, mesh.vertex_count(), vertices)) {
      return problem;
    }
    if (vertices.size() < 3) {
      return point_count_problem(c, vertices.size(), "a triangle strip needs at least 3");
    }
    for (std::size_t i = 0; i + 2 < vertices.size(); ++i) {
      if (i % 2 == 0) {
        mesh.add_triangle(vertices[i], vertices[i + 1], vertices[i + 2]);
      } else {
        mesh.add_triangle(vertices[i + 1], vertices[i], vertices[i + 2]);
      }
    }
  }
  return std::nullopt;
}

}  // namespace softbench
