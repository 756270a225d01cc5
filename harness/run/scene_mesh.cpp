// SPDX-License-Identifier: MIT
#include "harness/run/scene_mesh.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "harness/provenance.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

// How far apart the scene's features may be from the mesh's size before the two are taken to be
// in different units (a mesh in millimetres is 1000x a scene in metres).
constexpr double kUnitsFactor = 20.0;

// The points a scene places in space, from which its size follows: the instrument's path, the
// grasps (centre, radius and the scene grasp's path) and the fixed box (clipped to the mesh's box
// where the two overlap: a box reaching far past the body to select a half-space says nothing
// about its size). A fixed plane gives none (its point may lie anywhere on it: only how far the
// plane passes from the mesh says something), nor do vertex indices.
std::vector<Eigen::Vector3d> scene_points(const scenes::Scene& scene,
                                          const Eigen::Matrix<double, 3, 2>& mesh_box) {
  std::vector<Eigen::Vector3d> points;
  const auto around = [&](const Eigen::Vector3d& center, double radius) {
    points.push_back(center - Eigen::Vector3d::Constant(radius));
    points.push_back(center + Eigen::Vector3d::Constant(radius));
  };
  if (scene.fixed.box) {
    const Eigen::Vector3d lo = scene.fixed.box->min.cwiseMax(mesh_box.col(0));
    const Eigen::Vector3d hi = scene.fixed.box->max.cwiseMin(mesh_box.col(1));
    const bool overlap = (lo.array() <= hi.array()).all();
    points.push_back(overlap ? lo : scene.fixed.box->min);
    points.push_back(overlap ? hi : scene.fixed.box->max);
  }
  if (scene.grasp) {
    around(scene.grasp->center, scene.grasp->radius);
    for (const scenes::GraspKeyframe& frame : scene.grasp->path) {
      points.push_back(scene.grasp->center + frame.offset);
    }
  }
  if (scene.instrument) {
    for (const scenes::InstrumentKeyframe& frame : scene.instrument->path) {
      points.push_back(frame.position);
    }
    if (scene.instrument->grasp) {
      around(scene.instrument->grasp->center, scene.instrument->grasp->radius);
    }
  }
  return points;
}

// "the mesh is 1000x larger (millimetres for metres?)"
std::string mismatch(double ratio, const char* larger_or_smaller, const char* guess) {
  const double decades = std::log10(ratio);
  std::string text = "the mesh is " + std::to_string(std::lround(ratio)) + "x " + larger_or_smaller;
  text += std::string(" (") + (std::abs(decades - 3.0) < 0.5 ? guess : "units mixed up?") + ")";
  return text;
}

std::string number(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

// Throws when the body's mesh is far larger or smaller than the scene set around it.
void check_units(const scenes::Scene& scene, const TetMesh& body, const TriMesh* instrument) {
  const Eigen::Matrix<double, 3, 2> box = bounding_box(body.rest_positions());
  const double diagonal = (box.col(1) - box.col(0)).norm();
  if (!(diagonal > 0.0)) {
    return;
  }
  const std::string where = scene.mesh.string() + ": its bounding-box diagonal is "
                            + number(diagonal) + " but scene " + scene.source.string();
  const std::string rule = ": scenes and their meshes are in metres";
  const std::vector<Eigen::Vector3d> points = scene_points(scene, box);
  double span = 0.0;  // of the scene's points
  if (!points.empty()) {
    Eigen::Vector3d lo = points.front();
    Eigen::Vector3d hi = points.front();
    for (const Eigen::Vector3d& point : points) {
      lo = lo.cwiseMin(point);
      hi = hi.cwiseMax(point);
    }
    span = (hi - lo).norm();
  }
  // The tool's own size counts as the scene's too when the mesh is the larger: a body 20 times
  // the probe's length is no organ.
  double scene_size = span;
  if (instrument != nullptr && instrument->num_vertices() > 0) {
    const Eigen::Matrix<double, 3, 2> tool = bounding_box(instrument->vertices);
    scene_size = std::max(scene_size, (tool.col(1) - tool.col(0)).norm());
  }
  if (scene_size > 0.0 && diagonal > kUnitsFactor * scene_size) {
    throw InputError(
        where + " places its fixed box, grasp and instrument within " + number(scene_size) + ": "
        + mismatch(diagonal / scene_size, "larger", "a mesh in millimetres for a scene in metres?")
        + rule);
  }
  if (span > kUnitsFactor * diagonal) {
    throw InputError(
        where + " places its fixed box, grasp and instrument within " + number(span) + ": "
        + mismatch(span / diagonal, "smaller", "a scene in millimetres for a mesh in metres?")
        + rule);
  }
  // How far the scene reaches from the mesh: its points, and the fixed plane, which must pass
  // within its tolerance of a vertex to select one.
  const Eigen::Vector3d center = 0.5 * (box.col(0) + box.col(1));
  const auto outside = [&](const Eigen::Vector3d& point) {
    return (point - point.cwiseMax(box.col(0)).cwiseMin(box.col(1))).norm();
  };
  double reach = 0.0;
  for (const Eigen::Vector3d& point : points) {
    reach = std::max(reach, outside(point));
  }
  if (scene.fixed.plane) {
    const scenes::Plane& plane = *scene.fixed.plane;
    const Eigen::Vector3d nearest =
        center - (center - plane.point).dot(plane.normal) * plane.normal;
    reach = std::max(reach, outside(nearest) - plane.tolerance);
  }
  if (reach > kUnitsFactor * diagonal) {
    throw InputError(
        where + " places its fixed region, grasp or instrument " + number(reach) + " away from it: "
        + mismatch(reach / diagonal, "smaller", "a scene in millimetres for a mesh in metres?")
        + rule);
  }
}

}  // namespace

double SceneMesh::diagonal() const {
  return bounding_box_diagonal(body.rest_positions());
}

SceneMesh read_scene_mesh(const scenes::Scene& scene) {
  std::shared_ptr<const TriMesh> instrument;
  if (scene.instrument) {
    instrument =
        std::make_shared<const TriMesh>(make_closed_surface(read_mesh(scene.instrument->mesh)));
  }
  SceneMesh mesh{make_tet_mesh(read_mesh(scene.mesh)), file_hash(scene.mesh.string()),
                 std::move(instrument)};
  check_units(scene, mesh.body, mesh.instrument.get());
  return mesh;
}

}  // namespace softbench::harness
