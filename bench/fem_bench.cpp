// SPDX-License-Identifier: MIT
// One step of the corotational FEM (models/corotational_fem/) on the shipped liver and its two
// refinements, per linear solver and thread count:
//
//   BM_FemStep/<variant>/<mesh>/threads:<T>
//
// Scene-like setting (as step_bench): E 3000 Pa, nu 0.3, 1060 kg/m^3, gravity -z, the vertices
// in the lowest 10% of the x extent pinned exactly, dt = 1/60 s, from rest. kWarmUpSteps steps
// first, then KeepRunningBatch: the liver is still sagging (large rotations) while it is timed.
//
// Counters (per step unless stated):
// - steps_per_s (rate), mean_iterations (CG), mean_factorizations (numeric Cholesky);
// - rotations_ms, assembly_ms, solve_ms, update_ms: the phases of the step, timed inside the
//   model with a steady clock (CorotationalFemModel::step_timed);
// - cholmod_match: after kMatchSteps steps from rest, RMS |x - x_cholmod| / RMS |x_cholmod - X|
//   against CHOLMOD with the same formulation and rotation (the solver's error relative to the
//   motion; the goal is < 0.01);
// - exact_match: the same against CHOLMOD with exact (SVD) rotations: the solver's and the
//   rotation method's error together.
//
// Variants: "cholmod", "cg", "cholesky_pcg" with the model's defaults on every mesh and thread
// count; on liver.msh with one thread also cg with other tolerances, rotation methods and the
// linear formulation (what the defaults trade).
//
// Threads: T is set with omp_set_num_threads inside the benchmark. CHOLMOD calls OpenBLAS,
// whose pthreads are separate (OPENBLAS_NUM_THREADS). Run with OMP_WAIT_POLICY=passive when the
// CHOLMOD variants matter (its OpenMP threads otherwise spin on the cores OpenBLAS needs); the
// CG variants' short parallel regions prefer the default (active) policy. The machine is shared
// and noisy: run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true and
// quote medians.
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "models/corotational_fem/corotational_fem.h"
#include "models/corotational_fem/corotational_fem_model.h"
#include "scenes/shipped_data.h"

#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace softbench {
namespace {

using Params = CorotationalFemParams;
using corotational_fem::CorotationalFemModel;
using corotational_fem::PhaseTimes;

const char* const kLivers[] = {"liver.msh", "liver_x4.msh", "liver_x16.msh"};
constexpr double kDt = 1.0 / 60.0;
constexpr int kWarmUpSteps = 10;
constexpr int kStepsPerBatch = 4;
/// 1 s of the sag, from rest: the liver swings down through its largest rotations.
constexpr int kMatchSteps = 60;
const Material kLiverMaterial{3000.0, 0.3, 1060.0};

struct Variant {
  std::string label;
  Params params;
  bool all_meshes = true;  ///< false: liver.msh and one thread only
};

Params with(Params::LinearSolver solver) {
  Params params;
  params.solver = solver;
  return params;
}

std::vector<Variant> variants() {
  std::vector<Variant> result{{"cholmod", with(Params::LinearSolver::kCholmod)},
                              {"cg", with(Params::LinearSolver::kConjugateGradient)},
                              {"cholesky_pcg", with(Params::LinearSolver::kCholeskyPcg)}};
  // liver.msh only, one thread: what the defaults trade.
  for (const double tolerance : {3e-2, 1e-3, 1e-4}) {
    Params params;
    params.cg_tolerance = tolerance;
    std::ostringstream label;
    label << "cg+tol_" << tolerance;
    result.push_back({label.str(), params, false});
  }
  for (const int iterations : {1, 2}) {
    Params params;
    params.rotation_iterations = iterations;
    result.push_back({"cg+quaternion_" + std::to_string(iterations), params, false});
  }
  Params by_svd;
  by_svd.rotation = Params::Rotation::kSvd;
  result.push_back({"cg+svd", by_svd, false});
  Params linear;
  linear.formulation = Params::Formulation::kLinear;
  result.push_back({"cg+linear", linear, false});
  return result;
}

const TetMesh& liver(const std::string& name) {
  static std::map<std::string, TetMesh> loaded;
  auto found = loaded.find(name);
  if (found == loaded.end()) {
    found = loaded.emplace(name, make_tet_mesh(read_mesh(scenes::shipped_data_file(name)))).first;
  }
  return found->second;
}

std::vector<PositionConstraint> pin_lowest_tenth_in_x(const TetMesh& mesh) {
  const Eigen::Matrix<double, 3, 2> bounds = bounding_box(mesh.rest_positions());
  const double limit = bounds(0, 0) + 0.1 * (bounds(0, 1) - bounds(0, 0));
  std::vector<PositionConstraint> pins;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.rest_positions()(0, v) < limit) {
      pins.push_back({v, mesh.rest_positions().col(v), kExact});
    }
  }
  return pins;
}

/// Positions after kMatchSteps steps from rest, cached per mesh and parameter set.
const Eigen::Matrix3Xd& positions_after_match_steps(const std::string& mesh_name,
                                                    const Params& params) {
  static std::map<std::string, Eigen::Matrix3Xd> cache;
  const std::string key = mesh_name + corotational_fem::param_table().to_json(params).dump();
  auto found = cache.find(key);
  if (found == cache.end()) {
    const TetMesh& mesh = liver(mesh_name);
    CorotationalFemModel model(mesh, kLiverMaterial, params);
    const std::vector<PositionConstraint> pins = pin_lowest_tenth_in_x(mesh);
    StepInput input;
    input.gravity = {0.0, 0.0, -9.81};
    input.constraints = pins;
    for (int step = 0; step < kMatchSteps; ++step) {
      model.step(kDt, input);
    }
    found = cache.emplace(key, model.positions()).first;
  }
  return found->second;
}

/// RMS |x - x_reference| / RMS |x_reference - X| after kMatchSteps steps.
double match(const std::string& mesh_name, const Params& params, const Params& reference) {
  const Eigen::Matrix3Xd& x = positions_after_match_steps(mesh_name, params);
  const Eigen::Matrix3Xd& x_reference = positions_after_match_steps(mesh_name, reference);
  const Eigen::Matrix3Xd& rest = liver(mesh_name).rest_positions();
  return std::sqrt((x - x_reference).colwise().squaredNorm().mean()
                   / (x_reference - rest).colwise().squaredNorm().mean());
}

void fem_step(benchmark::State& state,
              const Variant& variant,
              const std::string& mesh_name,
              int threads) {
  omp_set_num_threads(threads);
  const TetMesh& mesh = liver(mesh_name);
  CorotationalFemModel model(mesh, kLiverMaterial, variant.params);
  const std::vector<PositionConstraint> pins = pin_lowest_tenth_in_x(mesh);
  StepInput input;
  input.gravity = {0.0, 0.0, -9.81};
  input.constraints = pins;
  for (int step = 0; step < kWarmUpSteps; ++step) {
    model.step(kDt, input);
  }

  PhaseTimes phases;
  double iterations = 0.0;
  double factorizations = 0.0;
  bool finite = true;
  while (state.KeepRunningBatch(kStepsPerBatch)) {
    for (int step = 0; step < kStepsPerBatch; ++step) {
      const StepStats stats = model.step_timed(kDt, input, &phases);
      iterations += stats.iterations;
      factorizations += stats.factorizations;
      finite = finite && stats.finite;
    }
  }
  if (!finite) {
    state.SkipWithError("the model blew up: the timings are of NaN arithmetic");
    return;
  }
  const auto steps = static_cast<double>(state.iterations());
  state.counters["steps_per_s"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
  state.counters["mean_iterations"] = iterations / steps;
  state.counters["mean_factorizations"] = factorizations / steps;
  state.counters["rotations_ms"] = 1e3 * phases.rotations / steps;
  state.counters["assembly_ms"] = 1e3 * phases.assembly / steps;
  state.counters["solve_ms"] = 1e3 * phases.solve / steps;
  state.counters["update_ms"] = 1e3 * phases.update / steps;
  state.counters["vertices"] = mesh.num_vertices();
  state.counters["tets"] = mesh.num_tets();

  // Accuracy, outside the timed loop (cached: repetitions do not redo it).
  Params cholmod = variant.params;
  cholmod.solver = Params::LinearSolver::kCholmod;
  Params exact = cholmod;
  exact.rotation = Params::Rotation::kSvd;
  state.counters["cholmod_match"] = match(mesh_name, variant.params, cholmod);
  state.counters["exact_match"] = match(mesh_name, variant.params, exact);
}

void register_benchmarks() {
  for (const Variant& variant : variants()) {
    for (const char* mesh_name : kLivers) {
      if (!variant.all_meshes && std::string(mesh_name) != kLivers[0]) {
        continue;
      }
      for (const int threads : {1, 2}) {
        if (!variant.all_meshes && threads != 1) {
          continue;
        }
        benchmark::RegisterBenchmark(
            ("BM_FemStep/" + variant.label + "/" + mesh_name
             + "/threads:" + std::to_string(threads))
                .c_str(),
            [variant, mesh = std::string(mesh_name), threads](benchmark::State& state) {
              fem_step(state, variant, mesh, threads);
            })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
