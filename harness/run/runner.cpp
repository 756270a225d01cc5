// SPDX-License-Identifier: MIT
#include "harness/run/runner.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "geometry/shape_meshes.h"
#include "geometry/text_format.h"
#include "harness/interrupt.h"
#include "harness/run/decimated_series.h"
#include "harness/run/loaded_travel.h"
#include "harness/run/plausibility.h"
#include "harness/run/run_monitor.h"
#include "harness/run/scene_stepper.h"
#include "models/model_registry.h"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace softbench::harness {
namespace {

using Clock = std::chrono::steady_clock;

double milliseconds(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

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

/// One timing of every step, for its percentiles (an even subsample past kSeriesCapacity
/// steps) and its rate (over every timed step).
class StepTimes {
 public:
  void add(double ms) {
    kept_.offer(ms);
    total_ms_ += ms;
  }
  Percentiles percentiles() const { return harness::percentiles(kept_.values()); }
  double steps_per_second() const {
    return total_ms_ > 0.0 ? 1000.0 * static_cast<double>(kept_.offered()) / total_ms_ : 0.0;
  }

 private:
  DecimatedSeries<double> kept_{kSeriesCapacity};
  double total_ms_ = 0.0;
};

/// Of two samples, the one a thinned series keeps: the larger tool force, so the force curve
/// keeps its peaks (and the force read after a withdrawal is not thinned away).
bool larger_force(const StepSample& a, const StepSample& b) {
  return a.tool_force > b.tool_force;
}

/// Accumulates one model's metrics step by step (ModelRun's groups).
class RunRecorder {
 public:
  RunRecorder(const scenes::Scene& scene, const SceneMesh& mesh, ModelRun& run)
      : mesh_(mesh.body),
        run_(run),
        rest_volume_(mesh_volume(mesh.body)),
        masses_(lumped_masses(mesh.body, scene.material.density)),
        travel_(scene, mesh) {}

  void time(double step_ms, double step_with_collision_ms) {
    step_ms_.add(step_ms);
    step_with_collision_ms_.add(step_with_collision_ms);
  }

  void solver(const StepStats& stats) {
    total_iterations_ += stats.iterations;
    run_.solver.factorizations += stats.factorizations;
    run_.solver.linear_solves += stats.linear_solves;
    run_.solver.truncated_solves += stats.truncated_solves;
    run_.solver.max_constraint_error =
        std::max(run_.solver.max_constraint_error, stats.max_constraint_error);
  }

  /// After a step the monitor passed: the state's measures and the tool's.
  void state(const SoftBody& body, double free_speed, const SceneStepper& stepper, double time) {
    const Eigen::Matrix3Xd& x = body.positions();
    StabilityMetrics& stability = run_.stability;
    stability.max_speed = std::max(stability.max_speed, free_speed);
    stability.max_kinetic_energy =
        std::max(stability.max_kinetic_energy, kinetic_energy(masses_, body.velocities()));
    ShapeMetrics& shape = run_.shape;
    shape.final_inverted_tets = count_inverted_tets(mesh_, x);
    shape.max_inverted_tets = std::max(shape.max_inverted_tets, shape.final_inverted_tets);
    shape.volume_change = std::max(shape.volume_change,
                                   std::abs(mesh_volume(mesh_, x) - rest_volume_) / rest_volume_);
    StepSample sample;
    sample.time = time;
    sample.tool_displacement = stepper.loading().tool_displacement();
    sample.tool_force = stepper.loading().tool_force();
    run_.contact.peak_tool_force = std::max(run_.contact.peak_tool_force, sample.tool_force);
    travel_.observe(time, x, sample.tool_displacement);
    if (stepper.have_reference() && stepper.recovery().released()) {
      sample.recovery_residual = stepper.recovery().residual();
    }
    samples_.offer(sample, larger_force);
  }

  void finish(const SoftBody& body, const SceneStepper& stepper) {
    TimingMetrics& timing = run_.timing;
    timing.step_ms = step_ms_.percentiles();
    timing.steps_per_second = step_ms_.steps_per_second();
    timing.step_with_collision_ms = step_with_collision_ms_.percentiles();
    timing.steps_per_second_with_collision = step_with_collision_ms_.steps_per_second();
    run_.samples = std::move(samples_).take();
    const Loading& loading = stepper.loading();
    run_.contact.max_penetration = loading.max_penetration();
    run_.contact.max_penetration_pressing = loading.max_penetration_pressing();
    run_.contact.lost_contact_vertices = loading.lost_contact_vertices();
    run_.contact.max_triangle_pairs = loading.max_triangle_pairs();
    run_.contact.loaded_travel = travel_.max();
    run_.contact.unsettled_steps = stepper.unsettled_contact_steps();
    run_.solver.mean_iterations = timing.steps_run > 0 ? total_iterations_ / timing.steps_run : 0.0;
    run_.solver.final_reaction_sum = body.constraint_forces().rowwise().sum();
    run_.shape.final_elastic_energy = body.elastic_energy();
    const RecoveryTracker& recovery = stepper.recovery();
    run_.recovery.measured = run_.stability.stable && recovery.released();
    run_.recovery.residual = recovery.residual();
    run_.recovery.time_to_one_percent = recovery.time_to_one_percent();
  }

 private:
  const TetMesh& mesh_;
  ModelRun& run_;
  double rest_volume_;
  Eigen::VectorXd masses_;
  LoadedTravel travel_;
  StepTimes step_ms_;
  StepTimes step_with_collision_ms_;
  DecimatedSeries<StepSample> samples_{kSeriesCapacity};
  double total_iterations_ = 0.0;
};

void print_outcome(const RunOptions& options, const ModelRun& run) {
  if (options.progress == nullptr) {
    return;
  }
  *options.progress << (options.live_progress ? "\r" : "") << run.model << ": "
                    << run.timing.steps_run << "/" << run.timing.steps_planned << " steps, "
                    << (run.timing.interrupted ? "interrupted, " : "")
                    << (run.stability.stable
                            ? "stable"
                            : "UNSTABLE at step " + std::to_string(*run.stability.diverged_at_step))
                    << ", median step " << run.timing.step_ms.median << " ms, "
                    << run.timing.steps_per_second << " steps/s over the timed steps' total";
  for (const Warning& warning : run.warnings) {
    *options.progress << "\n  warning: " << warning.id << ": " << warning.message;
  }
  *options.progress << "\n";
}

/// After a step ending at `end`: the body into `taken` at each of `times` (increasing) the step
/// reached. Half a step of slack: a time that rounding puts just past a step's end is that step's.
void capture(const std::vector<double>& times,
             double end,
             double dt,
             const TetMesh& mesh,
             const SoftBody& body,
             std::vector<Snapshot>& taken) {
  while (taken.size() < times.size() && end + 0.5 * dt > times[taken.size()]) {
    taken.push_back({times[taken.size()], body.positions(), mesh_volume(mesh, body.positions())});
  }
}

ModelRun run_model(const scenes::Scene& scene,
                   const SceneMesh& mesh,
                   const std::string& model_name,
                   const RunOptions& options) {
  const ModelInfo& info = builtin_models().at(model_name);
  std::unique_ptr<SoftBody> body =
      info.create(mesh.body, scene.material, scene.parameters_for(model_name),
                  {scene.source.string(), "/models/" + model_name});
  ModelRun run;
  run.model = model_name;
  run.params = body->parameters();
  run.vertices = mesh.body.num_vertices();
  run.tets = mesh.body.num_tets();
  run.timing.steps_planned = scene.num_steps();
  run.solver.memory_bytes = body->memory_bytes();

  SceneStepper stepper(scene, mesh);
  stepper.start(*body);
  RunMonitor monitor(mesh.body, scene.limits, mesh.diagonal());
  RunRecorder recorder(scene, mesh, run);
  for (int step = 0; step < run.timing.steps_planned; ++step) {
    const double start = step * scene.dt;
    const Clock::time_point before = Clock::now();
    double model_seconds = 0.0;
    const StepStats stats = stepper.step(step, *body, &model_seconds);
    const Clock::time_point after = Clock::now();
    if (step >= options.warmup_steps) {
      recorder.time(1000.0 * model_seconds, milliseconds(before, after));
    }
    run.timing.steps_run = step + 1;
    recorder.solver(stats);
    bool within_limits = true;
    try {
      within_limits = monitor.after_step(step, stats, *body, stepper.constraints());
    } catch (const Interrupted&) {
      if (!options.keep_interrupted) {
        throw;
      }
      // The step ran and was judged; the run ends after it, measured as far as it went.
      run.timing.interrupted = true;
      within_limits = !monitor.diverged();
    }
    if (!within_limits) {
      run.stability.stable = false;
      run.stability.diverged_at_step = monitor.divergence()->step;
      run.stability.divergence = monitor.divergence()->reason;
      break;
    }
    stepper.observe(step, *body);
    recorder.state(*body, monitor.free_speed(), stepper, start + scene.dt);
    capture(options.snapshot_times, start + scene.dt, scene.dt, mesh.body, *body, run.snapshots);
    capture(options.picture_times, start + scene.dt, scene.dt, mesh.body, *body, run.pictures);
    if (options.frames_every > 0 && step % options.frames_every == 0) {
      write_frame(options, model_name, step, mesh.body, *body);
    }
    if (run.timing.interrupted) {
      break;
    }
    if (options.progress != nullptr && options.live_progress && step % 30 == 0) {
      *options.progress << "\r" << model_name << ": step " << step + 1 << "/"
                        << run.timing.steps_planned << std::flush;
    }
  }
  recorder.finish(*body, stepper);
  run.warnings = judge_plausibility(run, scene);
  print_outcome(options, run);
  return run;
}

}  // namespace

std::vector<ModelRun> run_scene(const scenes::Scene& scene,
                                const SceneMesh& mesh,
                                const RunOptions& options) {
  const std::vector<std::string> names =
      options.models.empty() ? builtin_models().default_names() : options.models;
  for (const std::string& name : names) {
    builtin_models().at(name);  // an unknown name fails before any model runs
  }
  // Every block of the scene is read before any model runs, also those of models not run now:
  // a wrong key is found at once, not after the other models' runs (or never). Reading one
  // means building its model, on one cube of six tets: the same parameter check, at no cost.
  static const TetMesh one_cube = make_tet_mesh(box_tets(1, 1, 1, 0.01, 0.01, 0.01));
  for (const auto& [name, block] : scene.model_parameters) {
    // A block for a model this build leaves out is not an error in the scene.
    if (builtin_models().unavailable(name)) {
      continue;
    }
    if (!builtin_models().contains(name)) {
      try {
        builtin_models().at(name);
      } catch (const InputError& error) {
        throw InputError(scene.source.string() + ": /models/" + one_line(name) + ": "
                         + error.what());
      }
    }
    builtin_models().at(name).create(one_cube, scene.material, block,
                                     {scene.source.string(), "/models/" + name});
  }
  std::vector<ModelRun> runs;
  for (const std::string& name : names) {
    runs.push_back(run_model(scene, mesh, name, options));
    if (runs.back().timing.interrupted) {
      break;  // a stop was asked for: the models after it do not run
    }
  }
  return runs;
}

std::vector<ModelRun> run_scene(const scenes::Scene& scene, const RunOptions& options) {
  return run_scene(scene, read_scene_mesh(scene), options);
}

}  // namespace softbench::harness
