// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"
#include "geometry/tet_mesh.h"
#include "geometry/tri_mesh.h"

#include <string>
#include <vector>

namespace softbench {

struct MeshProblem {
  enum class Severity { kWarning, kError };
  Severity severity = Severity::kError;
  std::string message;  ///< "tet 12: zero volume (vertices 3 7 9 11)"; no file prefix
};

struct ValidationReport {
  std::vector<MeshProblem> problems;  ///< in the order found, capped per kind (see .cpp)
  int reoriented_tets = 0;            ///< inverted tets whose vertex order was flipped

  bool has_errors() const;
  /// The first error, prefixed with the source: "liver.msh: tet 12: zero volume (...)".
  std::string first_error(const std::string& source) const;
};

/// Tets whose volume is below this fraction of a regular tet with the same RMS edge length count
/// as degenerate (zero or near-zero volume). SOFA's liver.msh has a worst quality of 0.079.
inline constexpr double kDegenerateTetQuality = 1e-6;

/// Checks the tet part of `data` without changing it: finite coordinates, indices in range,
/// no repeated vertex in a tet, no degenerate tet (errors); inverted tets and vertices no tet
/// uses (warnings here; make_tet_mesh decides what is fatal).
ValidationReport validate_tets(const MeshData& data);

/// Swaps two corners of every tet with negative signed volume so all are positively oriented.
/// Returns how many were flipped. Indices must be in range.
int orient_tets_positively(const Eigen::Matrix3Xd& vertices, Eigen::Matrix4Xi& tets);

/// Builds a TetMesh from `data`: errors throw InputError naming data.source and the element;
/// inverted tets are reoriented (a warning, counted in the report); unreferenced vertices are an
/// error (a simulated vertex needs mass). `report`, if given, receives every problem found.
TetMesh make_tet_mesh(const MeshData& data, ValidationReport* report = nullptr);

/// Checks the triangle part of `data` as a surface: finite coordinates, indices in range,
/// repeated vertices in a triangle, zero-area triangles, unreferenced vertices (warnings), and
/// when `require_closed` open edges, non-manifold edges and inconsistent orientation (errors;
/// warnings otherwise).
ValidationReport validate_surface(const MeshData& data, bool require_closed);

/// A closed, manifold, consistently oriented surface from `data`, with unreferenced vertices
/// dropped and the orientation made outward (positive enclosed volume). Throws InputError naming
/// data.source otherwise.
TriMesh make_closed_surface(const MeshData& data);

}  // namespace softbench
