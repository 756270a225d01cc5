// SPDX-License-Identifier: MIT
#include "scenes/scene_regions.h"

#include "geometry/input_error.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/text_format.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace softbench::scenes {
namespace {

bool inside(const Box& box, const Eigen::Vector3d& point) {
  return (point.array() >= box.min.array()).all() && (point.array() <= box.max.array()).all();
}

bool within_band(const Plane& plane, const Eigen::Vector3d& point) {
  return std::abs((point - plane.point).dot(plane.normal)) <= plane.tolerance;
}

}  // namespace

std::vector<int> fixed_vertices(const Scene& scene, const TetMesh& mesh) {
  const FixedRegion& fixed = scene.fixed;
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const int num_vertices = mesh.num_vertices();
  std::vector<int> selected;
  for (std::size_t i = 0; i < fixed.vertices.size(); ++i) {
    const int vertex = fixed.vertices[i];
    if (vertex < 0 || vertex >= num_vertices) {
      throw InputError(scene.source.string() + ": /fixed/vertices/" + std::to_string(i)
                       + ": expected a vertex index in [0, " + std::to_string(num_vertices - 1)
                       + "] (" + scene.mesh.string() + " has " + std::to_string(num_vertices)
                       + " vertices), got " + std::to_string(vertex));
    }
    selected.push_back(vertex);
  }
  for (int vertex = 0; vertex < num_vertices; ++vertex) {
    const Eigen::Vector3d point = rest.col(vertex);
    if ((fixed.box && inside(*fixed.box, point))
        || (fixed.plane && within_band(*fixed.plane, point))) {
      selected.push_back(vertex);
    }
  }
  std::sort(selected.begin(), selected.end());
  selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
  return selected;
}

std::vector<SupportedVertex> supported_vertices(const Scene& scene, const TetMesh& mesh) {
  std::vector<SupportedVertex> supported;
  if (scene.supports.empty()) {
    return supported;
  }
  const std::vector<int> fixed = fixed_vertices(scene, mesh);
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  for (int vertex = 0; vertex < mesh.num_vertices(); ++vertex) {
    if (std::binary_search(fixed.begin(), fixed.end(), vertex)) {
      continue;
    }
    // The normals' span, one Gram-Schmidt step per plane: a plane parallel to one already
    // counted adds nothing.
    Eigen::Matrix3d held = Eigen::Matrix3d::Zero();
    bool selected = false;
    for (const Plane& plane : scene.supports) {
      if (!within_band(plane, rest.col(vertex))) {
        continue;
      }
      selected = true;
      const Eigen::Vector3d normal = plane.normal - held * plane.normal;
      if (normal.norm() > 1e-6) {
        const Eigen::Vector3d unit = normal.normalized();
        held += unit * unit.transpose();
      }
    }
    if (selected) {
      supported.push_back({vertex, held});
    }
  }
  return supported;
}

std::vector<int> required_fixed_vertices(const Scene& scene,
                                         const TetMesh& mesh,
                                         const std::string& command,
                                         const std::string& reason) {
  std::vector<int> selected = fixed_vertices(scene, mesh);
  if (selected.empty()) {
    const FixedRegion& fixed = scene.fixed;
    std::string what = "absent (a free body)";
    if (!fixed.vertices.empty() || fixed.box || fixed.plane) {
      // Coordinates in millimetres on a mesh in metres are the usual cause: show the span.
      const Eigen::Matrix<double, 3, 2> bounds = bounding_box(mesh.rest_positions());
      what = "selects no vertex of " + scene.mesh.string() + " (its vertices span "
             + format_vector(bounds.col(0)) + " to " + format_vector(bounds.col(1)) + ")";
    }
    throw InputError(scene.source.string() + ": /fixed: " + what + "; " + command
                     + " needs a fixed region: " + reason);
  }
  return selected;
}

Eigen::Vector3d rest_centre_of_mass(const TetMesh& mesh) {
  const Eigen::VectorXd masses = lumped_masses(mesh, 1.0);
  return mesh.rest_positions() * masses / masses.sum();
}

Eigen::Matrix3Xd initial_velocities(const Scene& scene, const TetMesh& mesh) {
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  Eigen::Matrix3Xd velocities = Eigen::Matrix3Xd::Zero(3, rest.cols());
  if (!scene.initial_velocity) {
    return velocities;
  }
  const InitialVelocity& motion = *scene.initial_velocity;
  const Eigen::Vector3d center = motion.center ? *motion.center : rest_centre_of_mass(mesh);
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    velocities.col(v) = motion.linear + motion.angular.cross(rest.col(v) - center);
  }
  for (const int vertex : fixed_vertices(scene, mesh)) {
    velocities.col(vertex).setZero();  // held at rest for the whole scene
  }
  return velocities;
}

std::vector<int> grasped_vertices(const Scene& scene, const TetMesh& mesh) {
  if (scene.grasp) {
    return surface_vertices_within(scene, mesh, scene.grasp->center, scene.grasp->radius, "/grasp");
  }
  if (scene.instrument && scene.instrument->grasp) {
    return surface_vertices_within(scene, mesh, scene.instrument->grasp->center,
                                   scene.instrument->grasp->radius, "/instrument/grasp");
  }
  return {};  // nothing is grasped
}

std::vector<int> surface_vertices_within(const Scene& scene,
                                         const TetMesh& mesh,
                                         const Eigen::Vector3d& center,
                                         double radius,
                                         const std::string& pointer) {
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const Eigen::Matrix3Xi triangles = boundary_triangles(mesh.tets());
  std::vector<bool> on_surface(static_cast<std::size_t>(mesh.num_vertices()), false);
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      on_surface[static_cast<std::size_t>(triangles(corner, t))] = true;
    }
  }
  std::vector<int> selected;
  double nearest = std::numeric_limits<double>::infinity();
  for (int vertex = 0; vertex < mesh.num_vertices(); ++vertex) {
    if (!on_surface[static_cast<std::size_t>(vertex)]) {
      continue;
    }
    const double distance = (rest.col(vertex) - center).norm();
    nearest = std::min(nearest, distance);
    if (distance <= radius) {
      selected.push_back(vertex);
    }
  }
  if (selected.empty()) {
    throw InputError(scene.source.string() + ": " + pointer + ": selects no surface vertex of "
                     + scene.mesh.string() + " within radius " + format_number(radius)
                     + " of center " + format_vector(center) + " (the nearest is "
                     + format_number(nearest) + " away)");
  }
  return selected;
}

Eigen::Vector3d grasp_offset(const Grasp& grasp, double time) {
  const std::vector<GraspKeyframe>& path = grasp.path;
  if (path.empty() || time < path.front().time) {
    return Eigen::Vector3d::Zero();
  }
  if (time >= path.back().time) {
    return path.back().offset;
  }
  // The first keyframe after `time`; the one before it is at or before `time`.
  const auto after =
      std::upper_bound(path.begin(), path.end(), time,
                       [](double t, const GraspKeyframe& frame) { return t < frame.time; });
  const GraspKeyframe& from = *(after - 1);
  const GraspKeyframe& to = *after;
  const double fraction = (time - from.time) / (to.time - from.time);
  return from.offset + fraction * (to.offset - from.offset);
}

}  // namespace softbench::scenes
