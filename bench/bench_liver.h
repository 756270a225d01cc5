// SPDX-License-Identifier: MIT
#pragma once

#include "bench/bench_smoke.h"
#include "geometry/tet_mesh.h"
#include "models/soft_body.h"

#include <benchmark/benchmark.h>

#include <map>
#include <span>
#include <string>
#include <vector>

// The scene-like set-up every model benchmark shares, so all of them time the same work.
namespace softbench::bench {

/// The steps a model step benchmark times after its warm-up (->Iterations), the same on every
/// mesh, thread count and machine: 2 s of the liver's sag from rest at the scenes' step. Google
/// Benchmark's own count follows the step's cost (half a second of steps), so it timed some 500
/// steps of the FEM's liver, most near rest and cheap, against 15 of liver_x16 in its first
/// swing, and the costs set side by side (across meshes, thread counts or models) were of
/// different motions; a faster build also moved its own window to cheaper steps.
inline constexpr int kTimedSteps = 120;
/// The same for a model whose step on the larger livers takes a second or more
/// (bullet_deformable: about 1 s on liver_x4, 2.5 s on liver_x16): fewer steps, the same on every
/// mesh still.
inline constexpr int kTimedStepsSlow = 8;
/// Whether the registry's `model` takes a second or more a step on the larger livers.
inline bool slow_model(const std::string& model) {
  return model == "bullet_deformable";
}
/// kTimedSteps, or kTimedStepsSlow for a slow model; `batch` (one batch) in a smoke run.
inline int timed_steps(bool slow, int batch) {
  return unless_smoke(slow ? kTimedStepsSlow : kTimedSteps, batch);
}

/// A shipped liver ("liver.msh", "liver_x4.msh", "liver_x16.msh"), read and validated once per
/// process on first use (not at registration, so running one benchmark loads one mesh).
const TetMesh& shipped_liver(const std::string& name);

/// Exact pins on the vertices in the lowest 10% of the x extent: the benchmarks' fixed region.
std::vector<PositionConstraint> pin_lowest_tenth_in_x(const TetMesh& mesh);

/// The input every model benchmark steps the liver with: gravity (-9.81 m/s^2 along z) and
/// `pins` (which must outlive it).
StepInput liver_input(std::span<const PositionConstraint> pins);

/// `compute()` (a double) the first time `key` is asked for in this process, the stored value
/// after: an accuracy check beside a timing that repetitions should not redo.
template <class Compute>
double once(const std::string& key, Compute compute) {
  static std::map<std::string, double> values;
  auto found = values.find(key);
  if (found == values.end()) {
    found = values.emplace(key, compute()).first;
  }
  return found->second;
}

/// The accuracy beside a speed figure: two bodies on `mesh` (one in the settings timed, one
/// converged, e.g. many more iterations) run `steps` steps of 1/60 s from rest, pinned as
/// pin_lowest_tenth_in_x and sagging under gravity; the RMS distance between their positions
/// over the converged body's RMS motion.
double sag_error(const TetMesh& mesh, SoftBody& approximate, SoftBody& converged, int steps);

/// Sums of a run's StepStats, and the counters every model benchmark reports from them.
struct StepTotals {
  double iterations = 0.0;
  double factorizations = 0.0;
  double residuals = 0.0;
  double linear_solves = 0.0;
  double truncated_solves = 0.0;
  bool finite = true;

  void add(const StepStats& stats) {
    iterations += stats.iterations;
    factorizations += stats.factorizations;
    residuals += stats.residual;
    linear_solves += stats.linear_solves;
    truncated_solves += stats.truncated_solves;
    finite = finite && stats.finite;
  }

  /// steps_per_s (a rate), the solves stopped at their cap (counted, and named in the label) and
  /// the means per step of iterations, factorizations, residual and
  /// linear solves, over state.iterations() steps. False, with the benchmark marked as an error,
  /// if a step blew up: the timings would be of NaN arithmetic.
  bool report(benchmark::State& state) const {
    if (!finite) {
      state.SkipWithError("the model blew up: the timings are of NaN arithmetic");
      return false;
    }
    const auto steps = static_cast<double>(state.iterations());
    state.counters["steps_per_s"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
    state.counters["mean_iterations"] = iterations / steps;
    state.counters["mean_factorizations"] = factorizations / steps;
    state.counters["mean_residual"] = residuals / steps;
    state.counters["mean_linear_solves"] = linear_solves / steps;
    // A solve stopped by its cap is timed at the cap: the label says so beside the time.
    state.counters["truncated_solves"] = truncated_solves;
    if (truncated_solves > 0.0) {
      state.SetLabel("TRUNCATED: " + std::to_string(static_cast<long long>(truncated_solves))
                     + " solves stopped at their iteration cap");
    }
    return true;
  }
};

/// The timed loop every model benchmark runs: `warm` (steps left out of the timing) `warm_up`
/// times (once in a smoke run), then `timed` in batches of `batch` while the benchmark asks for
/// more, its StepStats summed and reported (StepTotals::report; false if a step blew up).
template <class Warm, class Timed>
bool time_steps(benchmark::State& state, int warm_up, int batch, Warm warm, Timed timed) {
  for (int step = 0; step < unless_smoke(warm_up, 1); ++step) {
    warm();
  }
  StepTotals totals;
  while (state.KeepRunningBatch(batch)) {
    for (int step = 0; step < batch; ++step) {
      totals.add(timed());
    }
  }
  return totals.report(state);
}

}  // namespace softbench::bench
