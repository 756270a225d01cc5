// SPDX-License-Identifier: MIT
#include "meshgen/tetrahedralize.h"

#include "geometry/input_error.h"
#include "geometry/mesh_validation.h"

#include <tetgen.h>

#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace softbench::meshgen {
namespace {

std::string switches_for(const TetrahedralizeOptions& options) {
  // p: the input is a piecewise linear complex; z: number from zero; Q: quiet.
  std::ostringstream switches;
  switches.precision(17);
  switches << "pzQq" << options.radius_edge_ratio;
  if (options.min_dihedral_deg > 0.0) {
    switches << "/" << options.min_dihedral_deg;
  }
  if (options.max_volume > 0.0) {
    switches << "a" << options.max_volume;
  }
  if (options.preserve_surface) {
    switches << "Y";
  }
  return switches.str();
}

std::string tetgen_failure(int code) {
  switch (code) {
    case 1:
      return "out of memory";
    case 3:
      return "the surface intersects itself";
    case 4:
    case 5:
      return "the surface has facets or edges too close to each other";
    case 10:
      return "the input is invalid";
    default:
      return "internal error (code " + std::to_string(code) + ")";
  }
}

// tetgenio frees its arrays with delete[] in its destructor, so they are allocated with new[].
void fill_input(const TriMesh& surface, tetgenio& input) {
  input.firstnumber = 0;
  input.numberofpoints = surface.num_vertices();
  input.pointlist = new REAL[static_cast<std::size_t>(3 * surface.num_vertices())];
  std::memcpy(input.pointlist, surface.vertices.data(),
              sizeof(REAL) * static_cast<std::size_t>(surface.vertices.size()));
  input.numberoffacets = surface.num_triangles();
  input.facetlist = new tetgenio::facet[static_cast<std::size_t>(surface.num_triangles())];
  for (int t = 0; t < surface.num_triangles(); ++t) {
    tetgenio::facet& facet = input.facetlist[t];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int corner = 0; corner < 3; ++corner) {
      facet.polygonlist[0].vertexlist[corner] = surface.triangles(corner, t);
    }
  }
}

MeshData read_output(const tetgenio& output) {
  MeshData mesh;
  mesh.source = "tetgen";
  mesh.vertices = Eigen::Map<const Eigen::Matrix3Xd>(output.pointlist, 3, output.numberofpoints);
  mesh.tetrahedra =
      Eigen::Map<const Eigen::Matrix4Xi>(output.tetrahedronlist, 4, output.numberoftetrahedra);
  mesh.triangles =
      Eigen::Map<const Eigen::Matrix3Xi>(output.trifacelist, 3, output.numberoftrifaces);
  // TetGen's corner order has the opposite handedness to TetMesh's. Checking each tet rather than
  // swapping blindly keeps this right should a TetGen version change its convention.
  orient_tets_positively(mesh.vertices, mesh.tetrahedra);
  return mesh;
}

// TetGen 1.5 crashes in its own clean-up (a double free in freememory on the error path) when it
// meets a self-intersecting surface, so intersections are looked for first with -d, which
// reports the offending triangles and returns normally.
void reject_self_intersections(const TriMesh& surface) {
  tetgenio input;
  tetgenio output;
  fill_input(surface, input);
  char switches[] = "pdzQ";
  ::tetrahedralize(switches, &input, &output);
  if (output.numberoftrifaces > 0) {
    throw InputError(
        "tetrahedralize: the surface intersects itself (" + std::to_string(output.numberoftrifaces)
        + " triangles involved, e.g. at vertices " + std::to_string(output.trifacelist[0]) + " "
        + std::to_string(output.trifacelist[1]) + " " + std::to_string(output.trifacelist[2])
        + "); remesh it (--surface-vertices) or repair it first");
  }
}

}  // namespace

MeshData tetrahedralize(const TriMesh& surface, const TetrahedralizeOptions& options) {
  if (options.radius_edge_ratio < 1.1) {
    throw InputError("tetrahedralize: radius-edge ratio "
                     + std::to_string(options.radius_edge_ratio)
                     + " is below 1.1, which TetGen cannot guarantee to terminate");
  }
  if (options.max_volume < 0.0) {
    throw InputError("tetrahedralize: max volume must be >= 0");
  }
  reject_self_intersections(surface);
  tetgenio input;
  tetgenio output;
  fill_input(surface, input);
  std::string switches = switches_for(options);
  try {
    ::tetrahedralize(switches.data(), &input, &output);
  } catch (int code) {
    throw InputError("tetrahedralize: TetGen failed: " + tetgen_failure(code));
  }
  return read_output(output);
}

}  // namespace softbench::meshgen
