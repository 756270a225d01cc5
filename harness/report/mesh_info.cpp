// SPDX-License-Identifier: MIT
#include "harness/report/mesh_info.h"

#include <sstream>

namespace softbench::harness {
namespace {

void append(std::vector<MeshProblem>& to, const std::vector<MeshProblem>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

const char* severity_name(MeshProblem::Severity severity) {
  return severity == MeshProblem::Severity::kError ? "error" : "warning";
}

void inspect_tets(const MeshData& data, MeshInfo& info) {
  const ValidationReport report = validate_tets(data);
  append(info.problems, report.problems);
  if (report.has_errors()) {
    return;  // indices or coordinates are unusable: derived data would be garbage
  }
  Eigen::Matrix4Xi tets = data.tetrahedra;
  orient_tets_positively(data.vertices, tets);
  double volume = 0.0;
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    volume += signed_tet_volume(data.vertices.col(tets(0, t)), data.vertices.col(tets(1, t)),
                                data.vertices.col(tets(2, t)), data.vertices.col(tets(3, t)));
  }
  info.volume = volume;
  info.quality = tet_quality(data.vertices, tets);
  info.edges = static_cast<int>(unique_edges(tets).cols());
  const Eigen::Matrix3Xi boundary = boundary_triangles(tets);
  // Every interior face is shared by two tets, every boundary face belongs to one.
  info.faces = static_cast<int>((4 * tets.cols() + boundary.cols()) / 2);
  if (data.triangles.cols() == 0) {
    info.triangles = static_cast<int>(boundary.cols());
    info.triangles_from_boundary = true;
    info.surface = surface_topology(boundary, info.vertices);
    info.surface_area = surface_area(TriMesh{data.vertices, boundary});
    if (!info.surface.closed_manifold()) {
      info.problems.push_back(
          {MeshProblem::Severity::kError, "tet boundary is not a closed manifold surface"});
    }
  }
}

// The triangles stored next to tets (boundary elements in Gmsh files): only their topology
// matters, since the tets' validation already covered coordinates and interior vertices are
// rightly on no triangle.
void inspect_boundary_elements(const MeshData& data, MeshInfo& info) {
  info.surface = surface_topology(data.triangles, info.vertices);
  info.surface_area = surface_area(TriMesh{data.vertices, data.triangles});
}

void inspect_surface(const MeshData& data, MeshInfo& info) {
  // A closed surface is required only where there are no tets to bound the volume: an open
  // instrument surface is still a usable collision mesh, so openness is a warning there.
  const ValidationReport report = validate_surface(data, /*require_closed=*/false);
  append(info.problems, report.problems);
  if (report.has_errors()) {
    return;
  }
  info.surface = surface_topology(data.triangles, info.vertices);
  info.edges = static_cast<int>(unique_edges(data.triangles).cols());
  const TriMesh surface{data.vertices, data.triangles};
  info.surface_area = surface_area(surface);
  if (!info.surface.closed_manifold() || !info.surface.oriented()) {
    return;
  }
  info.volume = enclosed_volume(surface);
  if (*info.volume < 0.0) {
    info.problems.push_back(
        {MeshProblem::Severity::kWarning,
         "surface: oriented inward (enclosed volume < 0); loaders for simulation flip it"});
  }
  if (info.surface.components > 1) {
    info.problems.push_back(
        {MeshProblem::Severity::kWarning,
         "surface: " + std::to_string(info.surface.components) + " separate components"});
  }
}

nlohmann::json vector_json(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

bool MeshInfo::usable() const {
  for (const MeshProblem& problem : problems) {
    if (problem.severity == MeshProblem::Severity::kError) {
      return false;
    }
  }
  return true;
}

MeshInfo inspect_mesh(const MeshData& data) {
  MeshInfo info;
  info.source = data.source;
  info.vertices = static_cast<int>(data.vertices.cols());
  info.triangles = static_cast<int>(data.triangles.cols());
  info.tetrahedra = static_cast<int>(data.tetrahedra.cols());
  if (info.vertices > 0 && data.vertices.allFinite()) {
    info.bbox = bounding_box(data.vertices);
  }
  if (info.vertices == 0) {
    info.problems.push_back({MeshProblem::Severity::kError, "no vertices"});
  } else if (info.tetrahedra == 0 && info.triangles == 0) {
    info.problems.push_back({MeshProblem::Severity::kWarning, "no triangles or tetrahedra"});
  }
  if (info.tetrahedra > 0) {
    inspect_tets(data, info);
  }
  if (data.triangles.cols() > 0 && info.tetrahedra > 0) {
    inspect_boundary_elements(data, info);
  } else if (data.triangles.cols() > 0) {
    inspect_surface(data, info);
  }
  return info;
}

nlohmann::json to_json(const MeshInfo& info) {
  nlohmann::json json;
  json["file"] = info.source;
  json["vertices"] = info.vertices;
  json["triangles"] = info.triangles;
  json["triangles_from"] = info.triangles_from_boundary ? "tet boundary" : "file";
  json["tetrahedra"] = info.tetrahedra;
  json["faces"] = info.faces;
  json["edges"] = info.edges;
  json["bbox"] = {{"min", vector_json(info.bbox.col(0))},
                  {"max", vector_json(info.bbox.col(1))},
                  {"size", vector_json(info.bbox.col(1) - info.bbox.col(0))}};
  json["volume"] = info.volume ? nlohmann::json(*info.volume) : nlohmann::json(nullptr);
  json["surface_area"] =
      info.surface_area ? nlohmann::json(*info.surface_area) : nlohmann::json(nullptr);
  json["surface"] = {{"closed_manifold", info.surface.closed_manifold()},
                     {"oriented", info.surface.oriented()},
                     {"boundary_edges", info.surface.boundary_edges},
                     {"non_manifold_edges", info.surface.non_manifold_edges},
                     {"components", info.surface.components},
                     {"euler_characteristic", info.surface.euler_characteristic}};
  if (info.quality) {
    json["quality"] = {{"min_dihedral_deg", info.quality->min_dihedral_deg},
                       {"max_dihedral_deg", info.quality->max_dihedral_deg},
                       {"min_radius_ratio", info.quality->min_radius_ratio},
                       {"median_radius_ratio", info.quality->median_radius_ratio},
                       {"mean_radius_ratio", info.quality->mean_radius_ratio}};
  } else {
    json["quality"] = nullptr;
  }
  json["problems"] = nlohmann::json::array();
  for (const MeshProblem& problem : info.problems) {
    json["problems"].push_back(
        {{"severity", severity_name(problem.severity)}, {"message", problem.message}});
  }
  json["usable"] = info.usable();
  return json;
}

std::string to_text(const MeshInfo& info) {
  std::ostringstream out;
  out << "file: " << info.source << "\n";
  out << "vertices: " << info.vertices << "\n";
  out << "triangles: " << info.triangles << (info.triangles_from_boundary ? " (tet boundary)" : "")
      << "\n";
  out << "tetrahedra: " << info.tetrahedra << "\n";
  if (info.tetrahedra > 0) {
    out << "faces: " << info.faces << "\n";
  }
  out << "edges: " << info.edges << "\n";
  const Eigen::Vector3d size = info.bbox.col(1) - info.bbox.col(0);
  out << "bbox: [" << info.bbox(0, 0) << ", " << info.bbox(1, 0) << ", " << info.bbox(2, 0)
      << "] .. [" << info.bbox(0, 1) << ", " << info.bbox(1, 1) << ", " << info.bbox(2, 1)
      << "] (size " << size.x() << " x " << size.y() << " x " << size.z() << ")\n";
  if (info.volume) {
    out << "volume: " << *info.volume << "\n";
  }
  if (info.surface_area) {
    out << "surface area: " << *info.surface_area << "\n";
  }
  if (info.triangles > 0) {
    out << "surface: "
        << (info.surface.closed_manifold() ? "closed manifold" : "open or non-manifold") << ", "
        << (info.surface.oriented() ? "consistently oriented" : "misoriented") << ", "
        << info.surface.components << " component(s), Euler characteristic "
        << info.surface.euler_characteristic << "\n";
  }
  if (info.quality) {
    out << "quality: dihedral angles " << info.quality->min_dihedral_deg << " .. "
        << info.quality->max_dihedral_deg << " deg, radius ratio min "
        << info.quality->min_radius_ratio << " / median " << info.quality->median_radius_ratio
        << "\n";
  }
  if (info.problems.empty()) {
    out << "problems: none\n";
  } else {
    out << "problems: " << info.problems.size() << "\n";
    for (const MeshProblem& problem : info.problems) {
      out << "  " << severity_name(problem.severity) << ": " << problem.message << "\n";
    }
  }
  return out.str();
}

}  // namespace softbench::harness
