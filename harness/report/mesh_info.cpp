// SPDX-License-Identifier: MIT
#include "harness/report/mesh_info.h"

#include "collision/bvh.h"
#include "collision/bvh_collide.h"
#include "collision/exact_predicates.h"
#include "collision/tri_tri_projection.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace softbench::harness {
namespace {

using Point = Eigen::Vector3d;

// orient2d of a, b, c on the plane with normal n, projected along n's largest component (exact
// for points exactly in one plane: the projection is one-to-one there).
int orient_in_plane(const Point& n, const Point& a, const Point& b, const Point& c) {
  int drop = 0;
  n.cwiseAbs().maxCoeff(&drop);
  const int x = (drop + 1) % 3;
  const int y = (drop + 2) % 3;
  return collision::orient2d_exact(a[x], a[y], b[x], b[y], c[x], c[y]);
}

bool zero_area(const Point& a, const Point& b, const Point& c) {
  return (b - a).cross(c - a).squaredNorm() == 0.0;
}

// Triangles a and b, which the closed test found to meet, cross or overlap somewhere other than
// at the vertices they share (see find_self_intersections).
bool meet_beyond_shared(const std::array<Point, 3>& a, const std::array<Point, 3>& b) {
  std::array<int, 3> match_of_a{-1, -1, -1};  // the vertex of b at the same position
  int shared = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (a[i] == b[j]) {
        match_of_a[i] = j;
      }
    }
    shared += match_of_a[i] >= 0 ? 1 : 0;
  }
  if (shared == 0) {
    return true;
  }
  if (zero_area(a[0], a[1], a[2]) || zero_area(b[0], b[1], b[2])) {
    return false;
  }
  if (shared == 3) {
    return true;  // the same triangle twice
  }
  if (shared == 2) {
    // Joined along an edge u-w: two planes meet only in the line uw, so they overlap only
    // when both lie in one plane with their third vertices on the same side of uw.
    const int ia = match_of_a[0] < 0 ? 0 : match_of_a[1] < 0 ? 1 : 2;
    const Point& u = a[(ia + 1) % 3];
    const Point& w = a[(ia + 2) % 3];
    const Point& pa = a[ia];
    const Point& pb = b[3 - match_of_a[(ia + 1) % 3] - match_of_a[(ia + 2) % 3]];
    if (collision::orient3d_exact(u, w, pa, pb) != 0) {
      return false;
    }
    const Point n = (w - u).cross(pa - u);
    const int side_a = orient_in_plane(n, u, w, pa);
    return side_a != 0 && side_a == orient_in_plane(n, u, w, pb);
  }
  // Joined at one vertex v: what they share is convex and holds v; if it holds more, it has a
  // corner w other than v. w lies on the edge opposite v in A or in B (then that edge meets the
  // other triangle at w), or on an edge from v, which ends in the other triangle there (at a1,
  // say, making the opposite edge a1 a2 meet it) or where the other's edge opposite v crosses
  // it. So: do the edges opposite v meet the other triangle?
  const int ia = match_of_a[0] >= 0 ? 0 : match_of_a[1] >= 0 ? 1 : 2;
  const int ib = match_of_a[ia];
  const Point& a1 = a[(ia + 1) % 3];
  const Point& a2 = a[(ia + 2) % 3];
  const Point& b1 = b[(ib + 1) % 3];
  const Point& b2 = b[(ib + 2) % 3];
  // An edge is tested as a triangle of zero area (the test reduces it exactly to the segment).
  return collision::tri_tri_projection(a1, a2, a2, b[0], b[1], b[2]).intersect()
         || collision::tri_tri_projection(b1, b2, b2, a[0], a[1], a[2]).intersect();
}

void report_self_intersections(const Eigen::Matrix3Xd& vertices,
                               const Eigen::Matrix3Xi& triangles,
                               MeshInfo& info) {
  const SelfIntersections found = find_self_intersections(vertices, triangles);
  info.self_intersecting_pairs = found.pairs;
  if (found.pairs == 0) {
    return;
  }
  std::string examples;
  for (const auto& [a, b] : found.examples) {
    examples += (examples.empty() ? "" : ", ") + std::to_string(a) + " and " + std::to_string(b);
  }
  info.problems.push_back(
      {MeshProblem::Severity::kError,
       "surface intersects itself: " + std::to_string(found.pairs)
           + " triangle pair(s) cross or overlap where they are not joined (e.g. triangles "
           + examples + ", 0-based); TetGen refuses such a surface"});
}

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
    report_self_intersections(data.vertices, boundary, info);
  }
}

// The triangles stored next to tets (boundary elements in Gmsh files): only their topology
// matters, since the tets' validation already covered coordinates and interior vertices are
// rightly on no triangle.
void inspect_boundary_elements(const MeshData& data, MeshInfo& info) {
  info.surface = surface_topology(data.triangles, info.vertices);
  info.surface_area = surface_area(TriMesh{data.vertices, data.triangles});
  if (data.vertices.allFinite() && data.triangles.minCoeff() >= 0
      && data.triangles.maxCoeff() < info.vertices) {
    report_self_intersections(data.vertices, data.triangles, info);
  }
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
  report_self_intersections(data.vertices, data.triangles, info);
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

SelfIntersections find_self_intersections(const Eigen::Matrix3Xd& vertices,
                                          const Eigen::Matrix3Xi& triangles,
                                          int max_examples) {
  SelfIntersections found;
  if (triangles.cols() < 2) {
    return found;
  }
  // Deep enough for leaves of about 8 triangles.
  constexpr int kLeaf = 8;
  int levels = 1;
  while (levels < collision::BvhSchedule::kMaxLevels
         && static_cast<double>(kLeaf) * std::pow(2.0, levels - 1)
                < static_cast<double>(triangles.cols())) {
    ++levels;
  }
  const collision::Bvh tree(vertices, triangles, collision::BvhSchedule::all_aabb(levels, kLeaf));
  collision::CollideBuffers buffers;
  std::vector<collision::TrianglePair> pairs;
  collision::collide(tree, vertices, tree, vertices, buffers, pairs);
  std::vector<std::pair<int, int>> crossing;
  for (const collision::TrianglePair& pair : pairs) {
    if (pair.a >= pair.b) {
      continue;  // each pair is found both ways round, and every triangle meets itself
    }
    std::array<Point, 3> a;
    std::array<Point, 3> b;
    for (int corner = 0; corner < 3; ++corner) {
      a[corner] = vertices.col(triangles(corner, pair.a));
      b[corner] = vertices.col(triangles(corner, pair.b));
    }
    if (meet_beyond_shared(a, b)) {
      crossing.emplace_back(pair.a, pair.b);
    }
  }
  std::sort(crossing.begin(), crossing.end());
  found.pairs = static_cast<int>(crossing.size());
  const auto examples = std::min<std::size_t>(crossing.size(), std::max(max_examples, 0));
  found.examples.assign(crossing.begin(), crossing.begin() + static_cast<std::ptrdiff_t>(examples));
  return found;
}

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
  json["self_intersecting_pairs"] = info.self_intersecting_pairs;
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
