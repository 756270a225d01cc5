// SPDX-License-Identifier: MIT
#include "harness/run/loaded_travel.h"

#include "geometry/mesh_topology.h"
#include "scenes/instrument_path.h"

#include <algorithm>

namespace softbench::harness {

LoadedTravel::LoadedTravel(const scenes::Scene& scene, const SceneMesh& mesh)
    : scene_(scene), mesh_(mesh) {
  if (scene.grasp) {
    start_ = scene.grasp->start;
    release_ = scene.grasp->release;
  } else if (scene.instrument && scene.instrument->grasp) {
    start_ = scene.instrument->grasp->start;
    release_ = scene.instrument->grasp->release;
  } else if (scene.instrument && mesh.instrument) {
    start_ = scene.instrument->start;
    release_ = scene.instrument->release;
    surface_ = boundary_triangles(mesh.body.tets());
    if (start_ <= 0.0) {
      before_ = std::make_unique<collision::MeshDistance>(mesh.body.rest_positions(), surface_,
                                                          collision::BvhSchedule::liver());
    }
  }
}

LoadedTravel::~LoadedTravel() = default;

void LoadedTravel::observe(double time,
                           const Eigen::Matrix3Xd& positions,
                           double tool_displacement) {
  const double half_step = 0.5 * scene_.dt;
  if (scene_.grasp) {
    if (time > start_ - half_step && time < release_ + half_step) {
      max_ = std::max(max_, tool_displacement);
    }
  } else if (scene_.instrument && scene_.instrument->grasp) {
    if (time > start_ - half_step && time < release_ + half_step) {
      const Eigen::Vector3d from =
          scenes::instrument_pose(*scene_.instrument, start_).translation();
      const Eigen::Vector3d now = scenes::instrument_pose(*scene_.instrument, time).translation();
      max_ = std::max(max_, (now - from).norm());
    }
  } else if (surface_.cols() > 0) {
    press(time, positions);
  }
}

void LoadedTravel::press(double time, const Eigen::Matrix3Xd& positions) {
  const double half_step = 0.5 * scene_.dt;
  if (!before_) {
    // The step ending nearest the instrument's start: the shape before it acts.
    if (time > start_ - half_step) {
      before_ = std::make_unique<collision::MeshDistance>(positions, surface_,
                                                          collision::BvhSchedule::liver());
    }
    return;
  }
  if (time > release_ + half_step) {
    return;
  }
  const Eigen::Isometry3d pose = scenes::instrument_pose(*scene_.instrument, time);
  const collision::Aabb bounds = before_->bounds();
  const Eigen::Matrix3Xd& tool = mesh_.instrument->vertices;
  double deepest = 0.0;
  for (Eigen::Index i = 0; i < tool.cols(); ++i) {
    const Eigen::Vector3d point = pose * Eigen::Vector3d(tool.col(i));
    if (bounds.contains(point)) {  // outside the box is outside the shape
      deepest = std::max(deepest, -before_->signed_distance(point));
    }
  }
  if (!(deepest > 0.0)) {
    return;  // not in the tissue's shape (yet, or any more)
  }
  // The distance to the nearest surface stops growing at half the tissue's thickness; how far
  // the tool moved on since it first reached in does not.
  if (!touched_) {
    touched_ = true;
    touch_origin_ = pose.translation();
    touch_depth_ = deepest;
  }
  max_ = std::max({max_, deepest, touch_depth_ + (pose.translation() - touch_origin_).norm()});
}

}  // namespace softbench::harness
