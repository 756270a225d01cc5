// SPDX-License-Identifier: MIT
#include "geometry/mesh_validation.h"

#include "geometry/input_error.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/text_format.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace softbench {
namespace {

using Severity = MeshProblem::Severity;

// A garbage file can have a problem in every element; past the first few of a kind, more lines
// only bury the other kinds, so the rest are counted in one summary line.
constexpr int kMaxListedPerKind = 10;

// Triangles whose area is below this fraction of an equilateral triangle with the same RMS edge
// length count as zero-area: the same fraction kDegenerateTetQuality uses for tets.
constexpr double kDegenerateTriangleQuality = kDegenerateTetQuality;

// A closed surface whose enclosed volume is below this fraction of area^(3/2) is flat (two
// sheets back to back) up to round-off: it has no inside, so no outward orientation. A sphere has
// 0.094.
constexpr double kFlatSurfaceVolumeFraction = 1e-12;

// Appends problems to a report: the first kMaxListedPerKind of each kind in full, then one
// "... and N more <kind>" line per kind at finish().
class ProblemLog {
 public:
  explicit ProblemLog(ValidationReport& report) : report_(report) {}

  // `kind` is plural, for the summary line ("inverted tets"). `describe` makes the message and
  // runs only for listed problems, so a million bad elements cost no million strings.
  template <typename Describe>
  void add(const std::string& kind, Severity severity, Describe&& describe) {
    if (++tally_for(kind, severity).count <= kMaxListedPerKind) {
      report_.problems.push_back({severity, describe()});
    }
  }

  void finish() {
    for (const Tally& tally : tallies_) {
      if (tally.count > kMaxListedPerKind) {
        report_.problems.push_back(
            {tally.severity,
             "... and " + std::to_string(tally.count - kMaxListedPerKind) + " more " + tally.kind});
      }
    }
  }

 private:
  struct Tally {
    std::string kind;
    Severity severity;
    int count = 0;
  };

  Tally& tally_for(const std::string& kind, Severity severity) {
    for (Tally& tally : tallies_) {
      if (tally.kind == kind && tally.severity == severity) {
        return tally;
      }
    }
    return tallies_.emplace_back(Tally{kind, severity, 0});
  }

  ValidationReport& report_;
  std::vector<Tally> tallies_;  // in order of first appearance, so the summary is deterministic
};

std::string format_point(const Eigen::Vector3d& x) {
  std::ostringstream out;
  out << '(' << x.x() << ", " << x.y() << ", " << x.z() << ')';
  return out.str();
}

template <typename Indices>
std::string format_indices(const Indices& indices) {
  std::ostringstream out;
  for (Eigen::Index k = 0; k < indices.size(); ++k) {
    out << (k == 0 ? "" : " ") << indices(k);
  }
  return out.str();
}

std::string element(const char* name, Eigen::Index index) {
  return std::string(name) + " " + std::to_string(index);
}

std::string with_source(const std::string& source, const std::string& message) {
  return source.empty() ? message : source + ": " + message;
}

std::string count_of(int count, const char* singular, const char* plural) {
  return std::to_string(count) + " " + (count == 1 ? singular : plural);
}

// Flags vertices with a NaN or infinite coordinate (always an error: no geometry survives them)
// and returns which vertices are finite.
std::vector<bool> check_vertices(const Eigen::Matrix3Xd& vertices, ProblemLog& log) {
  std::vector<bool> finite(static_cast<std::size_t>(vertices.cols()));
  for (Eigen::Index v = 0; v < vertices.cols(); ++v) {
    finite[static_cast<std::size_t>(v)] = vertices.col(v).allFinite();
    if (!finite[static_cast<std::size_t>(v)]) {
      log.add("vertices with non-finite coordinates", Severity::kError, [&] {
        return element("vertex", v) + ": non-finite coordinate " + format_point(vertices.col(v));
      });
    }
  }
  return finite;
}

// Checks the indices of cell `c` (a tet or a triangle, named `name`): in range, none repeated.
// Returns whether its vertices can be looked up and form a proper cell; marks the vertices it
// uses in `referenced` either way.
template <int Corners>
bool check_cell_indices(const Eigen::Matrix<int, Corners, Eigen::Dynamic>& cells,
                        Eigen::Index c,
                        const char* name,
                        Severity repeated_severity,
                        std::vector<bool>& referenced,
                        ProblemLog& log) {
  const int num_vertices = static_cast<int>(referenced.size());
  const auto cell = cells.col(c);
  for (int k = 0; k < Corners; ++k) {
    if (cell(k) >= 0 && cell(k) < num_vertices) {
      referenced[static_cast<std::size_t>(cell(k))] = true;
    }
  }
  for (int k = 0; k < Corners; ++k) {
    if (cell(k) < 0 || cell(k) >= num_vertices) {
      log.add(std::string(name) + "s with out-of-range vertex indices", Severity::kError, [&] {
        return element(name, c) + ": vertex index " + std::to_string(cell(k))
               + " out of range (mesh has " + std::to_string(num_vertices) + " vertices)";
      });
      return false;
    }
  }
  for (int i = 0; i < Corners; ++i) {
    for (int j = i + 1; j < Corners; ++j) {
      if (cell(i) == cell(j)) {
        log.add(std::string(name) + "s with repeated vertices", repeated_severity,
                [&] { return element(name, c) + ": repeated vertex " + std::to_string(cell(i)); });
        return false;
      }
    }
  }
  return true;
}

template <int Corners>
bool all_finite(const Eigen::Matrix<int, Corners, 1>& cell, const std::vector<bool>& finite) {
  return std::all_of(cell.data(), cell.data() + Corners,
                     [&](int v) { return finite[static_cast<std::size_t>(v)]; });
}

void check_unreferenced(const std::vector<bool>& referenced,
                        const char* used_by,
                        Severity severity,
                        ProblemLog& log) {
  for (std::size_t v = 0; v < referenced.size(); ++v) {
    if (!referenced[v]) {
      log.add("unreferenced vertices", severity, [&] {
        return element("vertex", static_cast<Eigen::Index>(v)) + ": used by no " + used_by;
      });
    }
  }
}

// 6 sqrt(2) |V| / l_rms^3: 1 for a regular tet, 0 for a flat one, whatever the size.
double tet_volume_quality(const Eigen::Matrix3Xd& x, const Eigen::Vector4i& tet, double volume) {
  double squared_edges = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      squared_edges += (x.col(tet(i)) - x.col(tet(j))).squaredNorm();
    }
  }
  const double rms_edge = std::sqrt(squared_edges / 6.0);
  return rms_edge > 0.0 ? 6.0 * std::sqrt(2.0) * std::abs(volume) / std::pow(rms_edge, 3) : 0.0;
}

// 4 sqrt(3) A / (sum of squared edges): 1 for an equilateral triangle, 0 for a flat one.
double triangle_area_quality(const Eigen::Matrix3Xd& x, const Eigen::Vector3i& tri) {
  const Eigen::Vector3d a = x.col(tri(1)) - x.col(tri(0));
  const Eigen::Vector3d b = x.col(tri(2)) - x.col(tri(0));
  const double squared_edges = a.squaredNorm() + b.squaredNorm() + (b - a).squaredNorm();
  const double area = 0.5 * a.cross(b).norm();
  return squared_edges > 0.0 ? 4.0 * std::sqrt(3.0) * area / squared_edges : 0.0;
}

// How strict the tet checks are and what they say about inverted tets. make_tet_mesh() cannot
// simulate a vertex without mass, and it reorients inverted tets once it knows the mesh is sound.
struct TetPolicy {
  Severity unreferenced_vertex = Severity::kWarning;
  const char* inverted_note = "";  // appended to each inverted-tet message
};

ValidationReport check_tets(const MeshData& data, const TetPolicy& policy) {
  ValidationReport report;
  if (data.tetrahedra.cols() == 0) {
    report.problems.push_back({Severity::kError, "no tetrahedra"});
    return report;
  }
  ProblemLog log(report);
  const std::vector<bool> finite = check_vertices(data.vertices, log);
  std::vector<bool> referenced(finite.size(), false);
  const Eigen::Matrix3Xd& x = data.vertices;

  for (Eigen::Index t = 0; t < data.tetrahedra.cols(); ++t) {
    const Eigen::Vector4i tet = data.tetrahedra.col(t);
    if (!check_cell_indices<4>(data.tetrahedra, t, "tet", Severity::kError, referenced, log)
        || !all_finite<4>(tet, finite)) {
      continue;
    }
    const double volume =
        signed_tet_volume(x.col(tet(0)), x.col(tet(1)), x.col(tet(2)), x.col(tet(3)));
    const double quality = tet_volume_quality(x, tet, volume);
    // Written to catch a NaN quality too (overflowing coordinates).
    if (!(quality >= kDegenerateTetQuality)) {
      log.add("degenerate tets", Severity::kError, [&] {
        return element("tet", t) + ": zero or near-zero volume (quality "
               + format_number(quality, 2) + ", vertices " + format_indices(tet) + ")";
      });
    } else if (volume < 0.0) {
      log.add("inverted tets", Severity::kWarning, [&] {
        return element("tet", t) + ": inverted (negative volume " + format_number(volume, 2) + ")"
               + policy.inverted_note;
      });
    }
  }

  check_unreferenced(referenced, "tetrahedron", policy.unreferenced_vertex, log);
  log.finish();
  return report;
}

// One example edge of each kind surface_topology() counts, by the same rules, for messages.
struct ProblemEdges {
  std::optional<std::pair<int, int>> open;
  std::optional<std::pair<int, int>> non_manifold;
  std::optional<std::pair<int, int>> misoriented;
};

ProblemEdges first_problem_edges(const Eigen::Matrix3Xi& triangles) {
  struct EdgeUse {
    int lo = 0;
    int hi = 0;
    bool forward = false;
    auto operator<=>(const EdgeUse&) const = default;
  };
  std::vector<EdgeUse> uses;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const Eigen::Vector3i tri = triangles.col(t);
    if (tri(0) == tri(1) || tri(1) == tri(2) || tri(2) == tri(0)) {
      continue;  // collapsed: surface_topology() ignores it too
    }
    for (int k = 0; k < 3; ++k) {
      const int from = tri(k);
      const int to = tri((k + 1) % 3);
      uses.push_back({std::min(from, to), std::max(from, to), from < to});
    }
  }
  std::sort(uses.begin(), uses.end());

  ProblemEdges examples;
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t end = first + 1;
    while (end < uses.size() && uses[end].lo == uses[first].lo && uses[end].hi == uses[first].hi) {
      ++end;
    }
    std::optional<std::pair<int, int>>* kind = nullptr;
    if (end - first == 1) {
      kind = &examples.open;
    } else if (end - first >= 3) {
      kind = &examples.non_manifold;
    } else if (uses[first].forward == uses[first + 1].forward) {
      kind = &examples.misoriented;
    }
    if (kind != nullptr && !kind->has_value()) {
      *kind = std::pair{uses[first].lo, uses[first].hi};  // the smallest edge of its kind
    }
    first = end;
  }
  return examples;
}

std::string for_example(const std::optional<std::pair<int, int>>& edge) {
  return edge ? ", e.g. " + std::to_string(edge->first) + "-" + std::to_string(edge->second) : "";
}

// Open, non-manifold and misoriented edges: errors for a surface that must be closed.
void check_surface_topology(const MeshData& data, Severity severity, ValidationReport& report) {
  const SurfaceTopology topology =
      surface_topology(data.triangles, static_cast<int>(data.vertices.cols()));
  if (topology.closed_manifold() && topology.oriented()) {
    return;
  }
  const ProblemEdges examples = first_problem_edges(data.triangles);
  if (topology.boundary_edges > 0) {
    report.problems.push_back(
        {severity,
         "surface: "
             + count_of(topology.boundary_edges, "open (boundary) edge", "open (boundary) edges")
             + for_example(examples.open)});
  }
  if (topology.non_manifold_edges > 0) {
    report.problems.push_back(
        {severity,
         "surface: "
             + count_of(topology.non_manifold_edges, "non-manifold edge", "non-manifold edges")
             + " (shared by three or more triangles)" + for_example(examples.non_manifold)});
  }
  if (topology.misoriented_edges > 0) {
    report.problems.push_back(
        {severity, "surface: "
                       + count_of(topology.misoriented_edges, "inconsistently oriented edge",
                                  "inconsistently oriented edges")
                       + " (both triangles traverse it in the same direction)"
                       + for_example(examples.misoriented)});
  }
}

// The surface without collapsed triangles and without the vertices no remaining triangle uses,
// renumbered in increasing order of the original index.
TriMesh compact_surface(const MeshData& data) {
  std::vector<int> kept_triangles;
  std::vector<int> new_index(static_cast<std::size_t>(data.vertices.cols()), -1);
  for (Eigen::Index t = 0; t < data.triangles.cols(); ++t) {
    const Eigen::Vector3i tri = data.triangles.col(t);
    if (tri(0) == tri(1) || tri(1) == tri(2) || tri(2) == tri(0)) {
      continue;
    }
    kept_triangles.push_back(static_cast<int>(t));
    for (int k = 0; k < 3; ++k) {
      new_index[static_cast<std::size_t>(tri(k))] = 0;
    }
  }
  int num_kept = 0;
  for (int& index : new_index) {
    if (index == 0) {
      index = num_kept++;
    }
  }

  TriMesh surface;
  surface.vertices.resize(3, num_kept);
  for (std::size_t v = 0; v < new_index.size(); ++v) {
    if (new_index[v] >= 0) {
      surface.vertices.col(new_index[v]) = data.vertices.col(static_cast<Eigen::Index>(v));
    }
  }
  surface.triangles.resize(3, static_cast<Eigen::Index>(kept_triangles.size()));
  for (std::size_t t = 0; t < kept_triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      surface.triangles(k, static_cast<Eigen::Index>(t)) =
          new_index[static_cast<std::size_t>(data.triangles(k, kept_triangles[t]))];
    }
  }
  return surface;
}

}  // namespace

bool ValidationReport::has_errors() const {
  return std::any_of(problems.begin(), problems.end(),
                     [](const MeshProblem& p) { return p.severity == Severity::kError; });
}

std::string ValidationReport::first_error(const std::string& source) const {
  for (const MeshProblem& problem : problems) {
    if (problem.severity == Severity::kError) {
      return with_source(source, problem.message);
    }
  }
  return "";
}

ValidationReport validate_tets(const MeshData& data) {
  return check_tets(data, TetPolicy{});
}

int orient_tets_positively(const Eigen::Matrix3Xd& vertices, Eigen::Matrix4Xi& tets) {
  int flipped = 0;
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    auto tet = tets.col(t);
    if (signed_tet_volume(vertices.col(tet(0)), vertices.col(tet(1)), vertices.col(tet(2)),
                          vertices.col(tet(3)))
        < 0.0) {
      // An odd permutation of the vertices flips the sign of the volume and nothing else.
      std::swap(tet(2), tet(3));
      ++flipped;
    }
  }
  return flipped;
}

TetMesh make_tet_mesh(const MeshData& data, ValidationReport* report) {
  TetPolicy policy{.unreferenced_vertex = Severity::kError};
  ValidationReport found = check_tets(data, policy);
  Eigen::Matrix4Xi tets = data.tetrahedra;
  const int reoriented = found.has_errors() ? 0 : orient_tets_positively(data.vertices, tets);
  if (reoriented > 0) {
    // The same problems again, now saying what was done about them; only a mesh that is built
    // has its tets reoriented, so the note cannot go in before the errors are known.
    policy.inverted_note = "; reoriented";
    found = check_tets(data, policy);
    found.reoriented_tets = reoriented;
  }
  const std::string error = found.first_error(data.source);
  if (report != nullptr) {
    *report = std::move(found);
  }
  if (!error.empty()) {
    throw InputError(error);
  }
  return TetMesh(data.vertices, std::move(tets));
}

ValidationReport validate_surface(const MeshData& data, bool require_closed) {
  ValidationReport report;
  if (data.triangles.cols() == 0) {
    report.problems.push_back({Severity::kError, "no triangles"});
    return report;
  }
  ProblemLog log(report);
  const std::vector<bool> finite = check_vertices(data.vertices, log);
  std::vector<bool> referenced(finite.size(), false);

  for (Eigen::Index t = 0; t < data.triangles.cols(); ++t) {
    const Eigen::Vector3i tri = data.triangles.col(t);
    if (!check_cell_indices<3>(data.triangles, t, "triangle", Severity::kWarning, referenced, log)
        || !all_finite<3>(tri, finite)) {
      continue;
    }
    const double quality = triangle_area_quality(data.vertices, tri);
    if (!(quality >= kDegenerateTriangleQuality)) {
      log.add("zero-area triangles", Severity::kWarning, [&] {
        return element("triangle", t) + ": zero or near-zero area (quality "
               + format_number(quality, 2) + ", vertices " + format_indices(tri) + ")";
      });
    }
  }
  check_unreferenced(referenced, "triangle", Severity::kWarning, log);
  log.finish();

  // Edges between vertices that do not exist mean nothing; those triangles are reported above.
  const bool indices_in_range =
      data.triangles.minCoeff() >= 0
      && data.triangles.maxCoeff() < static_cast<int>(data.vertices.cols());
  if (indices_in_range) {
    check_surface_topology(data, require_closed ? Severity::kError : Severity::kWarning, report);
  }
  return report;
}

TriMesh make_closed_surface(const MeshData& data) {
  const ValidationReport report = validate_surface(data, /*require_closed=*/true);
  if (report.has_errors()) {
    throw InputError(report.first_error(data.source));
  }
  TriMesh surface = compact_surface(data);
  const double volume = enclosed_volume(surface);
  const double area = surface_area(surface);
  if (!(std::abs(volume) > kFlatSurfaceVolumeFraction * std::pow(area, 1.5))) {
    throw InputError(with_source(data.source, "surface: encloses no volume (volume "
                                                  + format_number(volume, 2) + ", area "
                                                  + format_number(area, 2) + ")"));
  }
  if (volume < 0.0) {
    surface.triangles.row(1).swap(surface.triangles.row(2));
  }
  return surface;
}

}  // namespace softbench
