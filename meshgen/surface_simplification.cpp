// SPDX-License-Identifier: MIT
#include "meshgen/surface_simplification.h"

#include "geometry/input_error.h"

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_filter.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <cmath>
#include <vector>

namespace softbench::meshgen {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace collapse = CGAL::Surface_mesh_simplification;

SurfaceMesh to_cgal(const TriMesh& surface) {
  SurfaceMesh mesh;
  std::vector<SurfaceMesh::Vertex_index> handles;
  handles.reserve(static_cast<std::size_t>(surface.num_vertices()));
  for (int v = 0; v < surface.num_vertices(); ++v) {
    const auto& x = surface.vertices.col(v);
    handles.push_back(mesh.add_vertex(Point(x.x(), x.y(), x.z())));
  }
  for (int t = 0; t < surface.num_triangles(); ++t) {
    const auto& tri = surface.triangles.col(t);
    const auto face = mesh.add_face(handles[static_cast<std::size_t>(tri(0))],
                                    handles[static_cast<std::size_t>(tri(1))],
                                    handles[static_cast<std::size_t>(tri(2))]);
    if (face == SurfaceMesh::null_face()) {
      throw InputError("simplify_surface: triangle " + std::to_string(t)
                       + " cannot be added: the surface is not an oriented manifold");
    }
  }
  return mesh;
}

TriMesh from_cgal(SurfaceMesh& mesh) {
  mesh.collect_garbage();
  TriMesh surface;
  surface.vertices.resize(3, static_cast<Eigen::Index>(mesh.number_of_vertices()));
  for (const auto vertex : mesh.vertices()) {
    const Point& p = mesh.point(vertex);
    surface.vertices.col(static_cast<Eigen::Index>(vertex.idx())) << p.x(), p.y(), p.z();
  }
  surface.triangles.resize(3, static_cast<Eigen::Index>(mesh.number_of_faces()));
  Eigen::Index column = 0;
  for (const auto face : mesh.faces()) {
    int corner = 0;
    for (const auto vertex : CGAL::vertices_around_face(mesh.halfedge(face), mesh)) {
      surface.triangles(corner++, column) = static_cast<int>(vertex.idx());
    }
    ++column;
  }
  return surface;
}

}  // namespace

TriMesh simplify_surface(const TriMesh& surface, int target_vertices) {
  SurfaceMesh mesh = to_cgal(surface);
  if (!CGAL::is_closed(mesh)) {
    throw InputError("simplify_surface: the surface is not closed");
  }
  // Collapse to twice the target first: cheap, and it keeps the shape (Lindstrom-Turk). A closed
  // genus-0 triangle mesh has E = 3V - 6 edges; the stop predicate counts edges.
  const auto collapse_target_edges = static_cast<std::size_t>(3 * (2 * target_vertices) - 6);
  if (mesh.number_of_edges() > collapse_target_edges) {
    collapse::Count_stop_predicate<SurfaceMesh> stop(collapse_target_edges);
    collapse::Bounded_normal_change_filter<> no_flips;
    collapse::edge_collapse(mesh, stop, CGAL::parameters::filter(no_flips));
    mesh.collect_garbage();
  }
  // Then remesh isotropically to the target: edge collapse leaves long thin triangles, and a
  // tetrahedralization that must keep the surface inherits their slivers (min dihedral ~3 deg).
  // Equilateral triangles of edge L on area A: F = 4A / (sqrt(3) L^2) and V = F / 2 + 2. The
  // remesher's edges come out somewhat shorter than asked, so a second pass corrects L by the
  // count the first one reached (V ~ 1 / L^2).
  const double area = CGAL::Polygon_mesh_processing::area(mesh);
  double edge_length = std::sqrt(2.0 * area / (std::sqrt(3.0) * (target_vertices - 2)));
  SurfaceMesh remeshed;
  for (int pass = 0; pass < 2; ++pass) {
    remeshed = mesh;
    CGAL::Polygon_mesh_processing::isotropic_remeshing(
        faces(remeshed), edge_length, remeshed,
        CGAL::parameters::number_of_iterations(5).number_of_relaxation_steps(3));
    edge_length *= std::sqrt(static_cast<double>(remeshed.number_of_vertices()) / target_vertices);
  }
  mesh = std::move(remeshed);
  return from_cgal(mesh);
}

}  // namespace softbench::meshgen
