// SPDX-License-Identifier: MIT
#include "harness/run/scene_stepper.h"

#include "scenes/scene_regions.h"

namespace softbench::harness {

SceneStepper::SceneStepper(const scenes::Scene& scene, const SceneMesh& mesh)
    : scene_(scene),
      initial_velocities_(scene.initial_velocity
                              ? std::optional(scenes::initial_velocities(scene, mesh.body))
                              : std::nullopt),
      loading_(scene, mesh),
      has_tool_(scene.grasp.has_value() || scene.instrument.has_value()),
      forces_(Eigen::Matrix3Xd::Zero(3, mesh.body.num_vertices())),
      recovery_(scene.release_time(), mesh.diagonal()),
      reference_(mesh.body.rest_positions()),
      have_reference_(scene.reference_time() <= 0.0) {
}

void SceneStepper::start(SoftBody& body) const {
  if (initial_velocities_) {
    body.set_velocities(*initial_velocities_);
  }
}

StepInput SceneStepper::input(int step, const SoftBody& body) {
  const double start = step * scene_.dt;
  if (!have_reference_ && start + 0.5 * scene_.dt >= scene_.reference_time()) {
    reference_ = body.positions();
    have_reference_ = true;
  }
  StepInput input;
  input.gravity =
      start < scene_.gravity.off_at ? scene_.gravity.acceleration : Eigen::Vector3d::Zero();
  input.constraints =
      loading_.constraints(start, scene_.dt, body.positions(), body.velocities(), forces_);
  return input;
}

void SceneStepper::observe(int step, const SoftBody& body) {
  const double end = step * scene_.dt + scene_.dt;  // as the runner times its samples
  if (has_tool_) {
    forces_ = body.constraint_forces();
    loading_.observe(end, body.positions(), forces_);
  }
  if (have_reference_) {
    recovery_.observe(end, body.positions(), reference_);
  }
}

}  // namespace softbench::harness
