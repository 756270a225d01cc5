// SPDX-License-Identifier: MIT
#include "harness/run/scene_stepper.h"

#include "scenes/scene_regions.h"

#include <chrono>

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

StepStats SceneStepper::step(int step, SoftBody& body, double* model_seconds, double (*clock)()) {
  if (clock == nullptr) {
    clock = [] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
          .count();
    };
  }
  StepInput in = input(step, body);
  const bool contact = scene_.instrument.has_value();
  if (contact) {
    start_positions_ = body.positions();
    start_velocities_ = body.velocities();
  }
  double seconds = 0.0;
  const auto timed_step = [&] {
    const double before = clock();
    const StepStats stats = body.step(scene_.dt, in);
    seconds += clock() - before;
    return stats;
  };
  StepStats stats = timed_step();
  // The contact's active set: repeat the step from its start while it drops a pulling hold or
  // holds a vertex that ended inside the instrument. Every pass's solver work is counted.
  const int max_passes = contact ? scene_.instrument->contact_passes : 1;
  bool settled = !contact;
  for (int pass = 1; stats.finite && pass < max_passes; ++pass) {
    const auto refined = loading_.refine(body.positions(), body.constraint_forces());
    if (!refined) {
      settled = true;
      break;
    }
    body.set_state(start_positions_, start_velocities_);
    in.constraints = *refined;
    const StepStats again = timed_step();
    stats.iterations += again.iterations;
    stats.factorizations += again.factorizations;
    stats.linear_solves += again.linear_solves;
    stats.truncated_solves += again.truncated_solves;
    stats.residual = again.residual;
    stats.max_constraint_error = again.max_constraint_error;
    stats.finite = again.finite;
  }
  ran_out_of_passes_ = !settled && stats.finite;
  constraints_ = in.constraints;
  if (model_seconds != nullptr) {
    *model_seconds = seconds;
  }
  return stats;
}

void SceneStepper::observe(int step, const SoftBody& body) {
  const double end = step * scene_.dt + scene_.dt;  // as the runner times its samples
  if (has_tool_) {
    forces_ = body.constraint_forces();
    // Judged here, not in step(): the check is a measure, outside the step's timed work.
    if (ran_out_of_passes_ && !loading_.contact_settled(body.positions(), forces_)) {
      ++unsettled_contact_steps_;
    }
    ran_out_of_passes_ = false;
    loading_.observe(end, body.positions(), forces_);
  }
  if (have_reference_) {
    recovery_.observe(end, body.positions(), reference_);
  }
}

}  // namespace softbench::harness
