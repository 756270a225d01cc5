// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"

#include <filesystem>
#include <span>
#include <string>

namespace softbench {

// Mesh file readers. Each reads a whole file into MeshData (0-based indices) or throws InputError
// naming the file, the line (text formats) or element, and the problem: a missing or unreadable
// file, a truncated file, a count that disagrees with the data, an index out of range, a NaN or
// infinite coordinate, an unsupported element type or format version. Readers check syntax and
// index ranges only; geometric validity (volumes, manifoldness) is mesh_validation's job.

/// Wavefront OBJ: `v` and `f` (polygons fan-triangulated; negative indices resolved;
/// `f v/vt/vn` accepted). vt, vn, mtllib, usemtl, o, g, s, l are ignored.
MeshData read_obj(const std::filesystem::path& path);

/// Gmsh MSH, ASCII: version 1 ($NOD/$ELM), 2.2 and 4.1 ($Nodes/$Elements). Keeps triangles
/// (type 2) and linear tetrahedra (type 4); points and lines are skipped; other element types are
/// an error. Node tags need not be contiguous: they are remapped to 0..#V-1 in file order.
MeshData read_msh(const std::filesystem::path& path);

/// TetGen: `path` is the .node, .ele or .face file, or the base name without extension; reads
/// base.node plus base.ele and base.face when they exist. Honours the 0- or 1-based first index.
MeshData read_tetgen(const std::filesystem::path& path);

/// STL, binary or ASCII (told apart by the binary size formula, not the "solid" header, since
/// binary files often begin with "solid"). Vertices closer than `weld_tolerance` (relative to the
/// bounding-box diagonal) are merged.
MeshData read_stl(const std::filesystem::path& path, double weld_tolerance = 1e-9);

/// Legacy VTK (version 2.0-5.1 header), ASCII or BINARY (big-endian), DATASET POLYDATA (POLYGONS,
/// fan-triangulated) or UNSTRUCTURED_GRID (cell types 5 triangle and 10 tetra; others skipped).
MeshData read_vtk(const std::filesystem::path& path);

/// VTK XML UnstructuredGrid (.vtu) with ASCII data arrays, as write_vtu() produces.
MeshData read_vtu(const std::filesystem::path& path);

/// Dispatches on the extension (.obj .msh .node .ele .face .stl .vtk .vtu, case-insensitive).
/// An unknown extension or a file whose content does not match its format is an InputError.
MeshData read_mesh(const std::filesystem::path& path);

/// A per-vertex field written into a .vtu for ParaView (e.g. displacement, velocity).
struct VertexField {
  std::string name;
  const Eigen::Matrix3Xd* values = nullptr;  ///< 3 x #V
};

// Writers. Each writes the whole file (through a temporary and a rename, so a reader never sees a
// half-written file) or throws InputError when the path cannot be written.

/// OBJ with `v` and `f` lines (1-based), full double precision.
void write_obj(const std::filesystem::path& path, const MeshData& mesh);
/// Gmsh MSH 2.2 ASCII with the triangles (type 2) and tetrahedra (type 4) present.
void write_msh(const std::filesystem::path& path, const MeshData& mesh);
/// VTK XML UnstructuredGrid, ASCII, tets (and triangles if any), with optional vertex fields.
void write_vtu(const std::filesystem::path& path,
               const MeshData& mesh,
               std::span<const VertexField> fields = {});
/// TetGen base.node, base.ele (if tets) and base.face (if triangles), 0-based. `base` has no
/// extension.
void write_tetgen(const std::filesystem::path& base, const MeshData& mesh);

}  // namespace softbench
