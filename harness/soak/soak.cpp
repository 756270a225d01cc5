// SPDX-License-Identifier: MIT
#include "harness/soak/soak.h"

#include "geometry/input_error.h"
#include "geometry/mesh_measures.h"
#include "harness/interrupt.h"
#include "harness/run/decimated_series.h"
#include "harness/run/metrics.h"
#include "harness/run/run_monitor.h"
#include "harness/run/scene_stepper.h"
#include "models/model_registry.h"

#include <malloc.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>

namespace softbench::harness {
namespace {

using Clock = std::chrono::steady_clock;

/// How many cycles a soak keeps (DecimatedSeries): 1,000,000 steps of a 300-step scene are
/// 3,334 cycles, thinned to one in four.
constexpr std::size_t kCycleCapacity = 1024;

/// A field of /proc/self/status in bytes ("VmRSS", "VmHWM"), 0 where there is none.
std::size_t status_bytes(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(field + ":", 0) == 0) {
      std::istringstream value(line.substr(field.size() + 1));
      std::size_t kib = 0;
      value >> kib;
      return kib * 1024;
    }
  }
  return 0;
}

double process_cpu_seconds() {
  timespec now{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

/// J: kinetic + elastic (if the model has one) + the work gravity would need to bring the body
/// back to its rest shape, so a body at rest in its rest shape has 0.
struct EnergyParts {
  double kinetic = 0.0;
  double total = 0.0;
};
EnergyParts energy_of(const SoftBody& body,
                      const Eigen::VectorXd& masses,
                      const Eigen::Matrix3Xd& rest,
                      const Eigen::Vector3d& gravity) {
  EnergyParts parts;
  parts.kinetic = kinetic_energy(masses, body.velocities());
  const double elastic = body.elastic_energy();
  const Eigen::VectorXd lift = -((body.positions() - rest).transpose() * gravity);
  parts.total = parts.kinetic + (std::isfinite(elastic) ? elastic : 0.0) + masses.dot(lift);
  return parts;
}

double median_steps_per_second(std::vector<SoakCycle>::const_iterator begin,
                               std::vector<SoakCycle>::const_iterator end) {
  std::vector<double> rates;
  for (auto it = begin; it != end; ++it) {
    rates.push_back(it->steps_per_second);
  }
  return percentiles(rates).median;
}

}  // namespace

SoakReport run_soak(const scenes::Scene& scene, const SceneMesh& mesh, const SoakOptions& options) {
  const ModelInfo& info = builtin_models().at(options.model);
  const int cycle_steps = scene.num_steps();
  if (cycle_steps < 2) {
    throw InputError(scene.source.string() + ": /time/duration: a soak cycles the scene, which "
                     "needs at least two steps");
  }
  std::unique_ptr<SoftBody> body =
      info.create(mesh.body, scene.material, scene.parameters_for(options.model),
                  {scene.source.string(), "/models/" + options.model});
  SoakReport report;
  report.scene = scene.name;
  report.model = options.model;
  report.vertices = mesh.body.num_vertices();
  report.tets = mesh.body.num_tets();
  report.dt = scene.dt;
  report.steps_per_cycle = cycle_steps;
  report.steps_planned = options.steps;

  const Eigen::VectorXd masses = lumped_masses(mesh.body, scene.material.density);
  const double diagonal = mesh.diagonal();
  RunMonitor monitor(mesh.body, scene.limits, diagonal);
  DecimatedSeries<SoakCycle> cycles(kCycleCapacity);
  cycles.reserve_capacity();
  std::optional<Eigen::Matrix3Xd> first_end;
  const Clock::time_point soak_start = Clock::now();
  long long step_total = 0;
  for (int cycle = 1; step_total < options.steps && report.stable && !report.interrupted;
       ++cycle) {
    // A fresh loading each cycle (the tool back at its start, the contact's and the grasp's
    // state new); the body goes on from where the last cycle left it.
    SceneStepper stepper(scene, mesh);
    if (cycle == 1) {
      stepper.start(*body);
    }
    SoakCycle record;
    record.cycle = cycle;
    const Clock::time_point cycle_start = Clock::now();
    const double cpu_start = process_cpu_seconds();
    int steps_this_cycle = 0;
    for (int step = 0; step < cycle_steps && step_total < options.steps; ++step) {
      const StepStats stats = stepper.step(step, *body);
      ++step_total;
      ++steps_this_cycle;
      // SoakOptions::steps is at most kMaxSoakSteps: the step number fits an int.
      bool within_limits = true;
      try {
        within_limits = monitor.after_step(static_cast<int>(step_total - 1), stats, *body,
                                           stepper.constraints());
      } catch (const Interrupted&) {
        if (!options.keep_interrupted) {
          throw;
        }
        report.interrupted = true;
        break;
      }
      if (!within_limits) {
        report.stable = false;
        report.diverged_at_step = step_total - 1;
        report.divergence = monitor.divergence()->reason;
        break;
      }
      stepper.observe(step, *body);
      record.peak_tool_force = std::max(record.peak_tool_force, stepper.loading().tool_force());
      record.max_speed = std::max(record.max_speed, monitor.free_speed());
    }
    if (report.interrupted) {
      break;  // a cycle cut short ends nowhere the others do: its measures are not kept
    }
    const double wall = std::chrono::duration<double>(Clock::now() - cycle_start).count();
    record.steps = step_total;
    record.steps_per_second = wall > 0.0 ? steps_this_cycle / wall : 0.0;
    record.cpu_ms_per_step = 1000.0 * (process_cpu_seconds() - cpu_start) / steps_this_cycle;
    record.resident_bytes = status_bytes("VmRSS");
    record.peak_resident_bytes = status_bytes("VmHWM");
    record.heap_bytes = heap_in_use();
    const EnergyParts energy =
        energy_of(*body, masses, mesh.body.rest_positions(), scene.gravity.acceleration);
    record.energy = energy.total;
    record.kinetic_energy = energy.kinetic;
    if (!first_end) {
      first_end = body->positions();
    }
    record.shape_drift = rms_distance(body->positions(), *first_end) / diagonal;
    cycles.offer(record);
    if (options.progress != nullptr && (options.live_progress || cycle % 100 == 0)) {
      *options.progress << (options.live_progress ? "\r" : "") << options.model << ": cycle "
                        << cycle << ", " << step_total << "/" << options.steps << " steps, "
                        << static_cast<long long>(record.steps_per_second) << " steps/s, RSS "
                        << record.resident_bytes / (1024 * 1024) << " MiB"
                        << (options.live_progress ? "" : "\n") << std::flush;
    }
  }
  if (options.progress != nullptr && options.live_progress) {
    *options.progress << "\n";
  }
  report.steps_run = step_total;
  report.cycles = std::move(cycles).take();
  report.wall_seconds = std::chrono::duration<double>(Clock::now() - soak_start).count();
  summarise_soak(report);
  return report;
}

std::size_t heap_in_use() {
  const struct mallinfo2 info = ::mallinfo2();
  return info.uordblks + info.hblkhd;
}

void summarise_soak(SoakReport& report) {
  const std::vector<SoakCycle>& cycles = report.cycles;
  if (cycles.empty()) {
    return;
  }
  const std::size_t tenth = std::max<std::size_t>(1, cycles.size() / 10);
  report.resident_after_warmup = cycles[tenth - 1].resident_bytes;
  report.resident_at_end = cycles.back().resident_bytes;
  const SoakCycle& middle = cycles[(cycles.size() - 1) / 2];
  report.heap_at_half = middle.heap_bytes;
  report.heap_at_end = cycles.back().heap_bytes;
  const long long steps_in_second_half = cycles.back().steps - middle.steps;
  report.heap_growth_per_step =
      steps_in_second_half > 0 ? (static_cast<double>(report.heap_at_end) -
                                  static_cast<double>(report.heap_at_half)) /
                                     static_cast<double>(steps_in_second_half)
                               : 0.0;
  for (const SoakCycle& cycle : cycles) {
    report.peak_resident = std::max(report.peak_resident, cycle.peak_resident_bytes);
  }
  const SoakCycle& first = cycles.front();
  // The scale drift is measured against: the first cycle's energy, or (a body near its rest
  // energy) its kinetic energy, never zero.
  const double scale = std::max({std::abs(first.energy), first.kinetic_energy, 1e-300});
  report.energy_drift = (cycles.back().energy - first.energy) / scale;
  report.final_shape_drift = cycles.back().shape_drift;
  if (cycles.size() >= 3) {
    // The first cycle is left out: it includes the settling and the caches' first touch.
    const auto begin = cycles.begin() + 1;
    const std::size_t span = std::max<std::size_t>(1, (cycles.size() - 1) / 10);
    const double early = median_steps_per_second(begin, begin + static_cast<long>(span));
    const double late = median_steps_per_second(cycles.end() - static_cast<long>(span),
                                                 cycles.end());
    report.speed_ratio = early > 0.0 ? late / early : 1.0;
  }
}

}  // namespace softbench::harness
