// SPDX-License-Identifier: MIT
// One implicit step of the mass-spring model (models/mass_spring/) on the shipped liver, on one
// core, beside corotational_fem's in the same run:
//
//   BM_MassSpringStep/<variant>/liver.msh
//   BM_MassSpringStep/corotational_fem/liver.msh   (the peer: its defaults)
//
// Scene-like setting (as step_bench and fem_bench): E 3000 Pa, nu 0.3, 1060 kg/m^3, gravity -z,
// the vertices in the lowest 10% of the x extent pinned exactly, dt = 1/60 s, from rest;
// kWarmUpSteps steps first, then kTimedSteps timed (the same steps on every machine). One
// OpenMP thread (the liver is below every parallel threshold anyway). Read the CPU time: the
// machine is shared, and wall time counts the time the thread was descheduled; steps_per_s is
// per CPU second too.
//
// Variants: "defaults" (springs from E, undamped, "cg" with the SSOR preconditioner, cg_tolerance
// 1e-3), "block_jacobi" (the same with the other preconditioner), "thesis_springs" (k 180 N/m,
// c 5 N s/m, "given"), "tolerance_1e-6" (the defaults solved a thousand times tighter),
// "cholmod" (defaults solved by CHOLMOD).
//
// Counters (per step): steps_per_s, mean_iterations, mean_factorizations; springs_ms,
// assembly_ms, solve_ms, update_ms (MassSpringModel::step_timed's phases, steady clock);
// cholmod_match: after kMatchSteps steps from rest, RMS |x - x_cholmod| / RMS |x_cholmod - X|
// against the same parameters solved by CHOLMOD (the solver's error relative to the motion).
//
// Run: build/release/bench/mass_spring_bench --benchmark_repetitions=5
// --benchmark_report_aggregates_only=true, and quote the CPU-time medians.
//
// Results (2026-11-25, this 2-core EPYC VM, shared: load average 2-4; CPU-time medians of 5
// repetitions): see models/README.md ("mass_spring").
#include "bench/bench_liver.h"
#include "models/mass_spring/mass_spring.h"
#include "models/mass_spring/mass_spring_model.h"
#include "models/model_registry.h"

#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace softbench {
namespace {

using Params = MassSpringParams;
using mass_spring::MassSpringModel;
using mass_spring::PhaseTimes;

const char* const kLiver = "liver.msh";
constexpr double kDt = 1.0 / 60.0;
constexpr int kWarmUpSteps = 10;
constexpr int kStepsPerBatch = 4;
/// Every repetition times the same steps after the warm-up: 10 s of the liver's swing from rest.
/// Left to Google Benchmark, the count follows the machine's speed (as many steps as fit its
/// minimum time), and a slower machine timed an earlier part of the swing, where the solve
/// needs more iterations: two machines' figures were of different work.
constexpr int kTimedSteps = 600;
/// 1 s of the sag from rest.
constexpr int kMatchSteps = 60;
const Material kLiverMaterial{3000.0, 0.3, 1060.0};

struct Variant {
  std::string label;
  Params params;
};

std::vector<Variant> variants() {
  std::vector<Variant> result{{"defaults", Params{}}};
  Params jacobi;
  jacobi.preconditioner = Params::Preconditioner::kBlockJacobi;
  result.push_back({"block_jacobi", jacobi});
  Params thesis;
  thesis.stiffness_from = Params::StiffnessFrom::kGiven;
  thesis.stiffness = 180.0;
  thesis.damping = 5.0;
  result.push_back({"thesis_springs", thesis});
  Params tight;
  tight.cg_tolerance = 1e-6;
  result.push_back({"tolerance_1e-6", tight});
  Params cholmod;
  cholmod.solver = Params::LinearSolver::kCholmod;
  result.push_back({"cholmod", cholmod});
  return result;
}

/// Positions after kMatchSteps steps from rest, cached per parameter set.
const Eigen::Matrix3Xd& positions_after_match_steps(const Params& params) {
  static std::map<std::string, Eigen::Matrix3Xd> cache;
  const std::string key = mass_spring::param_table().to_json(params).dump();
  auto found = cache.find(key);
  if (found == cache.end()) {
    const TetMesh& mesh = bench::shipped_liver(kLiver);
    MassSpringModel model(mesh, kLiverMaterial, params);
    const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
    const StepInput input = bench::liver_input(pins);
    for (int step = 0; step < bench::unless_smoke(kMatchSteps, 2); ++step) {
      model.step(kDt, input);
    }
    found = cache.emplace(key, model.positions()).first;
  }
  return found->second;
}

void mass_spring_step(benchmark::State& state, const Variant& variant) {
  omp_set_num_threads(1);
  const TetMesh& mesh = bench::shipped_liver(kLiver);
  MassSpringModel model(mesh, kLiverMaterial, variant.params);
  const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
  const StepInput input = bench::liver_input(pins);
  PhaseTimes phases;
  if (!bench::time_steps(
          state, kWarmUpSteps, kStepsPerBatch, [&] { return model.step(kDt, input); },
          [&] { return model.step_timed(kDt, input, &phases); })) {
    return;
  }
  const auto steps = static_cast<double>(state.iterations());
  state.counters["springs_ms"] = 1e3 * phases.springs / steps;
  state.counters["assembly_ms"] = 1e3 * phases.assembly / steps;
  state.counters["solve_ms"] = 1e3 * phases.solve / steps;
  state.counters["update_ms"] = 1e3 * phases.update / steps;

  // Accuracy, outside the timed loop (cached: repetitions do not redo it). The CG's own settings
  // do not change CHOLMOD's solve: variants that differ only in them share one reference run.
  Params cholmod = variant.params;
  cholmod.solver = Params::LinearSolver::kCholmod;
  cholmod.preconditioner = Params{}.preconditioner;
  cholmod.cg_tolerance = Params{}.cg_tolerance;
  const Eigen::Matrix3Xd& x = positions_after_match_steps(variant.params);
  const Eigen::Matrix3Xd& x_cholmod = positions_after_match_steps(cholmod);
  state.counters["cholmod_match"] =
      std::sqrt((x - x_cholmod).colwise().squaredNorm().mean()
                / (x_cholmod - mesh.rest_positions()).colwise().squaredNorm().mean());
}

void peer_step(benchmark::State& state, const std::string& model_name) {
  omp_set_num_threads(1);
  const TetMesh& mesh = bench::shipped_liver(kLiver);
  const std::unique_ptr<SoftBody> body =
      builtin_models()
          .at(model_name)
          .create(mesh, kLiverMaterial, nullptr,
                  ParamSource{"mass_spring_bench", "/" + model_name});
  const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
  const StepInput input = bench::liver_input(pins);
  const auto step = [&] { return body->step(kDt, input); };
  bench::time_steps(state, kWarmUpSteps, kStepsPerBatch, step, step);
}

void register_benchmarks() {
  for (const Variant& variant : variants()) {
    benchmark::RegisterBenchmark(
        ("BM_MassSpringStep/" + variant.label + "/" + kLiver).c_str(),
        [variant](benchmark::State& state) { mass_spring_step(state, variant); })
        ->Iterations(bench::unless_smoke(kTimedSteps, kStepsPerBatch))
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark(
      (std::string("BM_MassSpringStep/corotational_fem/") + kLiver).c_str(),
      [](benchmark::State& state) { peer_step(state, "corotational_fem"); })
      ->Iterations(bench::unless_smoke(kTimedSteps, kStepsPerBatch))
      ->Unit(benchmark::kMillisecond);
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
