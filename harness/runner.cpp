// SPDX-License-Identifier: MIT
#include "harness/runner.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "harness/scene_stepper.h"
#include "models/model_registry.h"
#include "scenes/scene_regions.h"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <span>

namespace softbench::harness {
namespace {

using Clock = std::chrono::steady_clock;

void write_frame(const RunOptions& options,
                 const std::string& model,
                 int step,
                 const TetMesh& mesh,
                 const SoftBody& body) {
  const std::filesystem::path dir = options.frames_dir / model;
  std::filesystem::create_directories(dir);
  std::ostringstream name;
  name << "frame_" << std::setw(5) << std::setfill('0') << step << ".vtu";
  const Eigen::Matrix3Xd displacement = body.positions() - mesh.rest_positions();
  const VertexField fields[] = {{"displacement", &displacement}, {"velocity", &body.velocities()}};
  write_vtu(dir / name.str(), MeshData{body.positions(), {}, mesh.tets(), model}, fields);
}

double steps_per_second(const std::vector<double>& step_ms) {
  double total_ms = 0.0;
  for (double ms : step_ms) {
    total_ms += ms;
  }
  return total_ms > 0.0 ? 1000.0 * static_cast<double>(step_ms.size()) / total_ms : 0.0;
}

ModelRun run_model(const scenes::Scene& scene,
                   const TetMesh& mesh,
                   const std::string& model_name,
                   const RunOptions& options) {
  const ModelInfo& info = builtin_models().at(model_name);
  const nlohmann::json params = scene.parameters_for(model_name);
  std::unique_ptr<SoftBody> body =
      info.create(mesh, scene.material, params, {scene.source.string(), "/models/" + model_name});

  ModelRun run;
  run.model = model_name;
  run.params = body->parameters();
  run.vertices = mesh.num_vertices();
  run.tets = mesh.num_tets();
  run.steps_planned = scene.num_steps();
  run.memory_bytes = body->memory_bytes();

  const Eigen::Matrix<double, 3, 2> box = bounding_box(mesh.rest_positions());
  const double diagonal = (box.col(1) - box.col(0)).norm();
  const double rest_volume = mesh_volume(mesh);
  const Eigen::VectorXd masses = lumped_masses(mesh, scene.material.density);
  SceneStepper stepper(scene, mesh, diagonal);

  std::vector<double> step_ms;
  std::vector<double> step_with_collision_ms;
  step_ms.reserve(static_cast<std::size_t>(run.steps_planned));
  step_with_collision_ms.reserve(static_cast<std::size_t>(run.steps_planned));
  run.samples.reserve(static_cast<std::size_t>(run.steps_planned));
  double total_iterations = 0.0;
  for (int step = 0; step < run.steps_planned; ++step) {
    const double start = step * scene.dt;
    const Clock::time_point before_collision = Clock::now();
    const StepInput input = stepper.input(step, *body);
    const Clock::time_point before = Clock::now();
    const StepStats stats = body->step(scene.dt, input);
    const Clock::time_point after = Clock::now();
    if (step >= options.warmup_steps) {
      step_ms.push_back(std::chrono::duration<double, std::milli>(after - before).count());
      step_with_collision_ms.push_back(
          std::chrono::duration<double, std::milli>(after - before_collision).count());
    }
    run.steps_run = step + 1;
    total_iterations += stats.iterations;
    run.factorizations += stats.factorizations;
    run.linear_solves += stats.linear_solves;
    run.max_constraint_error = std::max(run.max_constraint_error, stats.max_constraint_error);

    const Eigen::Matrix3Xd& x = body->positions();
    const Eigen::Matrix3Xd& v = body->velocities();
    const bool finite = stats.finite && x.allFinite() && v.allFinite();
    const double speed = finite ? max_speed(v) : INFINITY;
    const double displacement =
        finite ? (x - mesh.rest_positions()).colwise().norm().maxCoeff() : INFINITY;
    if (!finite || speed > scene.limits.max_speed
        || displacement > scene.limits.max_displacement * diagonal) {
      run.stable = false;
      run.diverged_at_step = step;
      run.divergence = !finite ? "NaN or Inf in the state"
                       : speed > scene.limits.max_speed
                           ? "speed " + std::to_string(speed) + " m/s over the limit"
                           : "displacement over the limit";
      break;
    }
    run.max_speed = std::max(run.max_speed, speed);
    run.max_kinetic_energy = std::max(run.max_kinetic_energy, kinetic_energy(masses, v));
    run.max_inverted_tets = std::max(run.max_inverted_tets, count_inverted_tets(mesh, x));
    run.volume_change =
        std::max(run.volume_change, std::abs(mesh_volume(mesh, x) - rest_volume) / rest_volume);
    stepper.observe(step, *body);
    StepSample sample;
    sample.time = start + scene.dt;
    sample.tool_displacement = stepper.loading().tool_displacement();
    sample.tool_force = stepper.loading().tool_force();
    run.peak_tool_force = std::max(run.peak_tool_force, sample.tool_force);
    if (stepper.have_reference() && stepper.recovery().released()) {
      sample.recovery_residual = stepper.recovery().residual();
    }
    run.samples.push_back(sample);
    // Half a step of slack: a time that rounding puts just past a step's end is that step's.
    while (run.snapshots.size() < options.snapshot_times.size()
           && start + 1.5 * scene.dt > options.snapshot_times[run.snapshots.size()]) {
      run.snapshots.push_back(
          {options.snapshot_times[run.snapshots.size()], x, mesh_volume(mesh, x)});
    }
    if (options.frames_every > 0 && step % options.frames_every == 0) {
      write_frame(options, model_name, step, mesh, *body);
    }
    if (options.progress != nullptr && options.live_progress && step % 30 == 0) {
      *options.progress << "\r" << model_name << ": step " << step + 1 << "/" << run.steps_planned
                        << std::flush;
    }
  }
  run.step_ms = percentiles(step_ms);
  run.fps = steps_per_second(step_ms);
  run.step_with_collision_ms = percentiles(step_with_collision_ms);
  run.fps_with_collision = steps_per_second(step_with_collision_ms);
  const Loading& loading = stepper.loading();
  run.max_penetration = loading.max_penetration();
  run.max_penetration_pressing = loading.max_penetration_pressing();
  run.lost_contact_vertices = loading.lost_contact_vertices();
  run.max_triangle_pairs = loading.max_triangle_pairs();
  run.mean_iterations = run.steps_run > 0 ? total_iterations / run.steps_run : 0.0;
  run.final_elastic_energy = body->elastic_energy();
  run.final_reaction_sum = body->constraint_forces().rowwise().sum();
  const RecoveryTracker& recovery = stepper.recovery();
  run.recovery_measured = run.stable && recovery.released();
  run.recovery_residual = recovery.residual();
  run.time_to_1pct = recovery.time_to_one_percent();
  if (options.progress != nullptr) {
    *options.progress << (options.live_progress ? "\r" : "") << model_name << ": " << run.steps_run
                      << "/" << run.steps_planned << " steps, "
                      << (run.stable ? "stable"
                                     : "UNSTABLE at step " + std::to_string(*run.diverged_at_step))
                      << ", median step " << run.step_ms.median << " ms (" << run.fps
                      << " steps/s)\n";
  }
  return run;
}

}  // namespace

std::vector<ModelRun> run_scene(const scenes::Scene& scene, const RunOptions& options) {
  const std::vector<std::string> names =
      options.models.empty() ? builtin_models().default_names() : options.models;
  for (const std::string& name : names) {
    builtin_models().at(name);  // an unknown name fails before any model runs
  }
  for (const auto& [name, block] : scene.model_parameters) {
    // A block for a model this build leaves out is not an error in the scene.
    if (!builtin_models().contains(name) && !builtin_models().unavailable(name)) {
      try {
        builtin_models().at(name);
      } catch (const InputError& error) {
        throw InputError(scene.source.string() + ": /models/" + name + ": " + error.what());
      }
    }
  }
  const TetMesh mesh = make_tet_mesh(read_mesh(scene.mesh));
  std::vector<ModelRun> runs;
  for (const std::string& name : names) {
    runs.push_back(run_model(scene, mesh, name, options));
  }
  return runs;
}

}  // namespace softbench::harness
