// SPDX-License-Identifier: MIT
// The cost of one model step on the shipped livers, in a scene-like setting: the liver material
// (E 3000 Pa, nu 0.3, 1060 kg/m^3), gravity, and the vertices in the lowest 10 % of the x extent
// pinned. Every registered model runs with its defaults (BM_Step/<model>/<mesh>); the
// mass-spring model also runs with each spring set named whatever its defaults (young_modulus:
// Van Gelder's springs from E, undamped; thesis_springs: k 180 N/m, c 5 N s/m), and per
// integrator and solver (BM_Step/mass_spring:<variant>/<mesh>). bench/mass_spring_bench.cpp
// times the mass-spring step's phases on one core against corotational_fem. Every repetition
// times the same steps after kWarmUpSteps on every mesh and machine (bench::timed_steps: 2 s of
// the sag at the scenes' step), so the costs compared across meshes are of one motion.
// Time is wall-clock (the models may use OpenMP threads). On a machine with few cores, run with
// OMP_WAIT_POLICY=passive: CHOLMOD's OpenMP threads otherwise spin-wait on the cores its
// OpenBLAS threads need (liver.msh's factorisation: 30 ms instead of 16 ms on 2 cores).
#include "bench/bench_liver.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "models/model_registry.h"
#include "scenes/shipped_data.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace softbench {
namespace {

const char* const kLivers[] = {"liver.msh", "liver_x4.msh", "liver_x16.msh"};

/// The scenes' step.
constexpr double kSceneDt = 1.0 / 60.0;
/// Symplectic Euler with the thesis's springs (k 180 N/m, c 5 N s/m) is unstable at 1/60 s, and
/// still at 1e-4 s: the dashpots on the liver's lightest vertices (5 mg on liver_x16) need
/// dt c_total / m < 2. 1e-7 s is stable on all three livers; the cost of a step does not depend
/// on dt, but the name says which dt ran.
constexpr double kSymplecticDt = 1e-7;
constexpr int kWarmUpSteps = 10;
constexpr int kStepsPerBatch = 4;

struct Variant {
  std::string label;  ///< the benchmark name's model part
  std::string model;  ///< registry key
  nlohmann::json params;
  double dt = kSceneDt;
  /// Its step on liver_x16 takes about a second or more: bench::kTimedStepsSlow steps.
  bool slow = false;
};

std::vector<Variant> variants() {
  std::vector<Variant> result;
  for (const std::string& name : builtin_models().default_names()) {
    result.push_back({name, name, nullptr, kSceneDt, bench::slow_model(name)});
  }
  // The mass-spring model's two spring sets, named whatever the defaults are: springs from
  // Young's modulus (Van Gelder) without dashpots, and the thesis's k = 180 N/m, c = 5 N s/m.
  result.push_back({"mass_spring:young_modulus",
                    "mass_spring",
                    {{"stiffness_from", "young_modulus"}, {"damping", 0.0}},
                    kSceneDt});
  result.push_back({"mass_spring:thesis_springs",
                    "mass_spring",
                    {{"stiffness_from", "given"}, {"stiffness", 180.0}, {"damping", 5.0}},
                    kSceneDt});
  result.push_back({"mass_spring:implicit_euler+cg",
                    "mass_spring",
                    {{"integrator", "implicit_euler"}, {"solver", "cg"}},
                    kSceneDt});
  result.push_back({"mass_spring:implicit_euler+cholmod",
                    "mass_spring",
                    {{"integrator", "implicit_euler"}, {"solver", "cholmod"}},
                    kSceneDt,
                    /*slow=*/true});  // CHOLMOD refactorises: 0.8 s a step on liver_x16
  result.push_back({"mass_spring:symplectic_euler@dt=1e-7",
                    "mass_spring",
                    {{"integrator", "symplectic_euler"},
                     {"stiffness_from", "given"},
                     {"stiffness", 180.0},
                     {"damping", 5.0}},
                    kSymplecticDt});
  return result;
}

void step_benchmark(benchmark::State& state, const Variant& variant, const std::string& mesh_name) {
  const TetMesh& mesh = bench::shipped_liver(mesh_name);
  const Material material{3000.0, 0.3, 1060.0};
  const std::unique_ptr<SoftBody> body =
      builtin_models()
          .at(variant.model)
          .create(mesh, material, variant.params, ParamSource{"step_bench", "/" + variant.label});
  const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
  StepInput input;
  input.constraints = pins;
  for (int step = 0; step < kWarmUpSteps; ++step) {
    body->step(variant.dt, input);
  }

  bench::StepTotals totals;
  while (state.KeepRunningBatch(kStepsPerBatch)) {
    for (int step = 0; step < kStepsPerBatch; ++step) {
      totals.add(body->step(variant.dt, input));
    }
  }
  if (!totals.report(state)) {
    return;
  }
  state.counters["dt_s"] = variant.dt;
  state.counters["vertices"] = mesh.num_vertices();
}

void register_benchmarks() {
  for (const Variant& variant : variants()) {
    for (const char* mesh_name : kLivers) {
      benchmark::RegisterBenchmark(
          ("BM_Step/" + variant.label + "/" + mesh_name).c_str(),
          [variant, mesh = std::string(mesh_name)](benchmark::State& state) {
            step_benchmark(state, variant, mesh);
          })
          ->Iterations(bench::timed_steps(variant.slow, kStepsPerBatch))
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
