// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_builder.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

// Cell handling shared by the legacy VTK and the XML .vtu readers. Each function returns the
// problem it found (without a location, which the caller adds), or nullopt.
namespace softbench {

/// Cells as VTK 5.1 and .vtu store them: cell c is connectivity[offsets[c] .. offsets[c + 1]).
struct VtkCellArray {
  std::vector<std::int64_t> offsets{0};  ///< #cells + 1 entries, starting at 0
  std::vector<std::int64_t> connectivity;
  std::size_t size() const { return offsets.size() - 1; }
};

/// The VTK cell types softbench keeps; every other valid type is skipped.
inline constexpr std::int64_t kVtkTriangle = 5;
inline constexpr std::int64_t kVtkTetra = 10;

/// Converts the legacy layout "n i_1 ... i_n" per cell, checking it holds exactly `cell_count`
/// cells.
std::optional<std::string> cells_from_legacy(std::span<const std::int64_t> legacy,
                                             std::size_t cell_count,
                                             VtkCellArray& cells);
/// Offsets must start at 0, never decrease and end at the connectivity size.
std::optional<std::string> check_offsets(const VtkCellArray& cells);
/// Appends the triangles (type 5) and tets (type 10) of an unstructured grid, skipping other
/// cell types; indices must lie in [0, mesh.vertex_count()).
std::optional<std::string> append_cells_by_type(const VtkCellArray& cells,
                                                std::span<const std::int64_t> types,
                                                MeshBuilder& mesh);
/// POLYDATA POLYGONS, fan-triangulated.
std::optional<std::string> append_polygons(const VtkCellArray& cells, MeshBuilder& mesh);
/// POLYDATA TRIANGLE_STRIPS, every other triangle flipped to keep the strip's orientation.
std::optional<std::string> append_triangle_strips(const VtkCellArray& cells, MeshBuilder& mesh);

}  // namespace softbench
