// SPDX-License-Identifier: MIT
// `softbench soak`: one body driven through its scene's loading again and again (the instrument
// presses and withdraws, or the grasp pulls and lets go, cycle after cycle) for millions of
// steps, to show what a short run cannot: memory that grows, energy that creeps, a state that
// drifts, a step that slows down, a NaN after an hour.
#pragma once

#include "harness/run/scene_mesh.h"
#include "scenes/scene.h"

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace softbench::harness {

/// The most steps a soak takes (a day at 10,000 steps/s), so a step number fits an int.
inline constexpr long long kMaxSoakSteps = 1000000000;

struct SoakOptions {
  std::string model;
  long long steps = 1000000;  ///< steps in all, over as many cycles as they make
  std::ostream* progress = nullptr;
  bool live_progress = false;
  /// Ctrl-C or SIGTERM ends the soak after the current step and run_soak returns what the whole
  /// cycles before it measured, marked interrupted (a stopped ten-hour soak keeps its hours);
  /// false: Interrupted is thrown.
  bool keep_interrupted = false;
};

/// The end of one cycle (the scene's duration): the body is back where the scene leaves it
/// (tool withdrawn or released, recovered as far as the scene lets it).
struct SoakCycle {
  int cycle = 0;            ///< 1-based
  long long steps = 0;      ///< steps run by the end of this cycle
  double steps_per_second = 0.0;      ///< this cycle's steps / its wall time (model + collision)
  double cpu_ms_per_step = 0.0;       ///< process CPU time (every thread) / step, this cycle
  std::size_t resident_bytes = 0;     ///< VmRSS at the cycle's end
  std::size_t peak_resident_bytes = 0;  ///< VmHWM at the cycle's end
  /// Bytes the allocator has handed out and not had back at the cycle's end (heap_in_use):
  /// exact where resident memory moves in pages and with the allocator's caching, so a leak of
  /// a few bytes a step shows within a few cycles instead of after a million steps.
  std::size_t heap_bytes = 0;
  /// J: kinetic + elastic (when the model has an elastic energy) + gravitational, relative to
  /// the rest shape at rest, at the cycle's end.
  double energy = 0.0;
  double kinetic_energy = 0.0;
  /// RMS distance of the cycle's end shape from the first cycle's / rest bbox diagonal.
  double shape_drift = 0.0;
  double peak_tool_force = 0.0;  ///< N, within the cycle
  double max_speed = 0.0;        ///< m/s, free vertices, within the cycle
};

struct SoakReport {
  std::string scene;
  std::string model;
  int vertices = 0;
  int tets = 0;
  double dt = 0.0;
  int steps_per_cycle = 0;
  long long steps_planned = 0;
  long long steps_run = 0;
  bool stable = true;
  /// Stopped by Ctrl-C or SIGTERM after steps_run steps (SoakOptions::keep_interrupted): the
  /// cycles are the whole ones before the stop.
  bool interrupted = false;
  std::optional<long long> diverged_at_step;
  std::string divergence;
  /// Every cycle up to the series' capacity, then an even thinning over the whole soak.
  std::vector<SoakCycle> cycles;
  double wall_seconds = 0.0;

  // What the cycles say (soak_summary).
  /// Resident memory after the warm-up (the end of the first tenth of the cycles, at least the
  /// first) and at the end; growth = end - warm-up.
  std::size_t resident_after_warmup = 0;
  std::size_t resident_at_end = 0;
  std::size_t peak_resident = 0;
  /// Heap in use at the end of the middle cycle and of the last (SoakCycle::heap_bytes), and
  /// the growth between the two per step (bytes; 0 when the soak allocates nothing it keeps).
  /// The middle, not the first tenth: the heap's warm-up (the allocator's per-thread caches,
  /// containers reaching their working sizes) lasts some cycles, and a short soak's first
  /// tenth is its first cycle.
  std::size_t heap_at_half = 0;
  std::size_t heap_at_end = 0;
  double heap_growth_per_step = 0.0;
  /// (energy at the last cycle's end - at the first's) / max(|first|, kinetic scale).
  double energy_drift = 0.0;
  double final_shape_drift = 0.0;
  /// Median steps/s of the last tenth of the cycles over the first tenth's (after the first).
  double speed_ratio = 1.0;
};

/// Soaks `model` on `scene`: cycles of the scene's steps (a fresh loading each cycle, the body
/// carried on) until options.steps, judged every step by RunMonitor (a blow-up ends the soak
/// and is reported). Throws InputError for an unknown model or a scene with fewer than two
/// steps, Interrupted on Ctrl-C unless options.keep_interrupted.
SoakReport run_soak(const scenes::Scene& scene, const SceneMesh& mesh, const SoakOptions& options);

/// Bytes in use in the allocator's arenas (glibc's mallinfo2: allocated chunks plus mmapped
/// blocks, every arena), 0 where that is not known.
std::size_t heap_in_use();

/// Fills the summary fields of `report` from its cycles.
void summarise_soak(SoakReport& report);

}  // namespace softbench::harness
