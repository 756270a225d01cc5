// SPDX-License-Identifier: MIT
// XPBD (models/xpbd/) on the shipped liver and its two refinements:
//
// - BM_XpbdSweep/<mesh>: one Gauss-Seidel sweep over the tets (both constraints of every tet
//   projected once, nothing held): the step's inner loop, run `substeps * iterations` times a
//   step. Counter ns_per_tet. The goal on liver.msh: under 0.3 ms on one core (the
//   PositionBasedDynamics library's XPBD sweep takes 0.64 ms on 4455 tets on this kind of
//   machine).
// - BM_XpbdStep/<mesh>/substeps:<n>: one full step (dt 1/60 s, gravity, the vertices in the
//   lowest 10% of x pinned exactly, from rest, kWarmUpSteps steps first: the liver is still
//   sagging while timed) with n substeps of one sweep, the default 10 and the cheaper
//   settings, the stability bound off (XpbdParams::stability_ratio 0) so that n is what runs
//   (the default bound asks 10 on the liver at 1/60 s, more on the refinements' smaller tets). Counters: steps_per_s, mean_iterations (sweeps a step), mean_residual (xpbd.h),
//   and error_vs_converged: the RMS distance after 60 steps (1 s of sag) to the same run at
//   100 substeps, over the RMS sag (bench::sag_error, outside the timing): what the cheaper
//   settings cost in accuracy.
//
// Each iteration is timed on the thread's CPU clock (UseManualTime), one thread: the model is
// serial, and on the shared 2-core machine wall time includes time the thread was
// descheduled. Run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true and
// quote medians. Measured figures: models/README.md, "xpbd".
#include "bench/bench_liver.h"
#include "bench/thread_cpu_clock.h"
#include "models/xpbd/xpbd.h"
#include "models/xpbd/xpbd_model.h"

#include <benchmark/benchmark.h>
#include <omp.h>

#include <memory>
#include <string>
#include <vector>

namespace softbench {
namespace {

constexpr double kDt = 1.0 / 60.0;
constexpr int kWarmUpSteps = 10;
constexpr int kConvergedSubsteps = 100;
const Material kLiverMaterial{3000.0, 0.3, 1060.0};
const char* const kLivers[] = {"liver.msh", "liver_x4.msh", "liver_x16.msh"};

void sweep_benchmark(benchmark::State& state, const std::string& liver) {
  omp_set_num_threads(1);
  const TetMesh& mesh = bench::shipped_liver(liver);
  const XpbdParams params;
  const std::unique_ptr<SoftBody> body = make_xpbd(mesh, kLiverMaterial, params);
  auto& model = dynamic_cast<xpbd::XpbdModel&>(*body);
  const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
  const StepInput input = bench::liver_input(pins);
  for (int step = 0; step < bench::unless_smoke(kWarmUpSteps, 1); ++step) {
    body->step(kDt, input);  // a deformed state: the sweep's corrections are not all zero
  }
  const double substep = kDt / params.substeps;
  for (auto _ : state) {
    const double start = bench::thread_cpu_us();
    model.sweep(substep);
    state.SetIterationTime(1e-6 * (bench::thread_cpu_us() - start));
    benchmark::DoNotOptimize(body->positions().data());
  }
  if (!body->positions().allFinite()) {
    state.SkipWithError("the sweep produced a NaN");
    return;
  }
  state.counters["tets"] = model.num_tets();
  state.counters["ns_per_tet"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * model.num_tets(),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::OneK::kIs1000);
}

/// After 60 steps (1 s of sag) against the same run at kConvergedSubsteps, relative to its RMS
/// sag (outside the timing; cached, so repetitions do not redo it).
double error_vs_converged(const std::string& liver, int substeps) {
  return bench::once(liver + "/" + std::to_string(substeps), [&] {
    const TetMesh& mesh = bench::shipped_liver(liver);
    XpbdParams params;
    params.substeps = substeps;
    params.stability_ratio = 0.0;
    XpbdParams converged;
    converged.substeps = kConvergedSubsteps;
    const std::unique_ptr<SoftBody> approximate = make_xpbd(mesh, kLiverMaterial, params);
    const std::unique_ptr<SoftBody> exact = make_xpbd(mesh, kLiverMaterial, converged);
    return bench::sag_error(mesh, *approximate, *exact, bench::unless_smoke(60, 2));
  });
}

void step_benchmark(benchmark::State& state, const std::string& liver, int substeps) {
  omp_set_num_threads(1);
  const TetMesh& mesh = bench::shipped_liver(liver);
  XpbdParams params;
  params.substeps = substeps;
  params.stability_ratio = 0.0;
  const std::unique_ptr<SoftBody> body = make_xpbd(mesh, kLiverMaterial, params);
  const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
  const StepInput input = bench::liver_input(pins);
  for (int step = 0; step < bench::unless_smoke(kWarmUpSteps, 1); ++step) {
    body->step(kDt, input);
  }
  bench::StepTotals totals;
  for (auto _ : state) {
    const double start = bench::thread_cpu_us();
    totals.add(body->step(kDt, input));
    state.SetIterationTime(1e-6 * (bench::thread_cpu_us() - start));
  }
  if (!totals.report(state)) {
    return;
  }
  state.counters["vertices"] = mesh.num_vertices();
  state.counters["tets"] = mesh.num_tets();
  state.counters["error_vs_converged"] = error_vs_converged(liver, substeps);
}

void register_benchmarks() {
  for (const char* liver : kLivers) {
    benchmark::RegisterBenchmark(("BM_XpbdSweep/" + std::string(liver)).c_str(),
                                 [liver](benchmark::State& state) {
                                   sweep_benchmark(state, liver);
                                 })
        ->Unit(benchmark::kMicrosecond)
        ->UseManualTime();
  }
  for (const char* liver : kLivers) {
    for (const int substeps : {10, 5, 2}) {
      benchmark::RegisterBenchmark(
          ("BM_XpbdStep/" + std::string(liver) + "/substeps:" + std::to_string(substeps)).c_str(),
          [liver, substeps](benchmark::State& state) { step_benchmark(state, liver, substeps); })
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime();
    }
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
