// SPDX-License-Identifier: MIT
// Projective Dynamics (models/projective_dynamics/) on the shipped livers, one core, in the
// scene-like setting of step_bench (gravity, the lowest 10% of x pinned, dt 1/60 s), against
// corotational_fem's default step in the same run:
//
// - BM_ProjectiveDynamicsStep/<variant>/<mesh>: one step. Counters: s_per_iteration (the
//   step's CPU time over its local/global iterations, the step's fixed work included: the
//   figure the per-iteration goal is about), and error_vs_converged, the RMS distance after 60
//   steps (1 s of sag) to the same run at 300 iterations a step, over the RMS sag (computed
//   outside the timing; not on liver_x16, where the converged run would take minutes): what the
//   variant's speed costs in accuracy.
// - BM_ProjectiveDynamicsStep/corotational_fem/<mesh>: the peer.
// - BM_ProjectiveDynamicsHolds/<pinned|contact|contact_refactorised>/liver.msh: what holds that
//   change every step cost, by multipliers on the kept factor (contact) or by refactorising
//   (contact_refactorised); holds_step() says how. mean_linear_solves less the 10 global
//   solves are the multiplier columns solved for.
//
// Run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true and quote medians;
// the measured figures are in models/README.md.
#include "bench/bench_liver.h"
#include "models/model_registry.h"
#include "models/projective_dynamics/projective_dynamics.h"

#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace softbench {
namespace {

const char* const kLivers[] = {"liver.msh", "liver_x4.msh", "liver_x16.msh"};
constexpr double kDt = 1.0 / 60.0;
constexpr int kWarmUpSteps = 10;
constexpr int kStepsPerBatch = 2;
constexpr int kAccuracySteps = 60;
const Material kLiverMaterial{3000.0, 0.3, 1060.0};

struct Variant {
  std::string label;
  nlohmann::json params;
};

std::vector<Variant> variants() {
  return {{"defaults", nlohmann::json::object()},
          {"no_chebyshev", {{"chebyshev_rho", 0.0}}},
          {"iterations:5", {{"iterations", 5}}},
          {"iterations:20", {{"iterations", 20}}}};
}

std::unique_ptr<SoftBody> make(const TetMesh& mesh,
                               const std::string& model,
                               const nlohmann::json& params) {
  return builtin_models().at(model).create(mesh, kLiverMaterial, params,
                                           ParamSource{"projective_dynamics_bench", "/" + model});
}

/// The variant's positions after kAccuracySteps against the converged run's, relative to the
/// converged run's RMS motion (bench::sag_error), once per (mesh, variant).
double error_vs_converged(const std::string& liver, const Variant& variant) {
  return bench::once(liver + "/" + variant.label, [&] {
    const TetMesh& mesh = bench::shipped_liver(liver);
    nlohmann::json converged = variant.params;
    converged["iterations"] = 300;
    const std::unique_ptr<SoftBody> exact = make(mesh, "projective_dynamics", converged);
    const std::unique_ptr<SoftBody> approximate =
        make(mesh, "projective_dynamics", variant.params);
    return bench::sag_error(mesh, *approximate, *exact, bench::unless_smoke(kAccuracySteps, 2));
  });
}

void model_step(benchmark::State& state,
                const std::string& liver,
                const std::string& model,
                const nlohmann::json& params) {
  omp_set_num_threads(1);
  const TetMesh& mesh = bench::shipped_liver(liver);
  const std::unique_ptr<SoftBody> body = make(mesh, model, params);
  const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
  const StepInput input = bench::liver_input(pins);
  double iterations = 0.0;
  const auto step = [&] { return body->step(kDt, input); };
  const auto timed = [&] {
    const StepStats stats = body->step(kDt, input);
    iterations += stats.iterations;
    return stats;
  };
  if (!bench::time_steps(state, kWarmUpSteps, kStepsPerBatch, step, timed)) {
    return;
  }
  state.counters["s_per_iteration"] = benchmark::Counter(
      iterations, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

enum class Holds { kPinned, kContact, kContactRefactorised };

/// The liver pinned as in model_step, plus (but for kPinned) a contact patch that changes every
/// step: 16 of the 24 highest free vertices, a window moving by one vertex a step, each held
/// 1 mm below its rest height. kContact: held along the vertical only, not anchoring, the
/// way the instrument contact holds (multipliers on the kept factor). kContactRefactorised: the
/// same vertices held fully and anchoring, so they are eliminated from the factor, which is
/// redone each time the set changes: the alternative, timed.
void holds_step(benchmark::State& state, Holds holds) {
  omp_set_num_threads(1);
  const TetMesh& mesh = bench::shipped_liver("liver.msh");
  const std::unique_ptr<SoftBody> body = make(mesh, "projective_dynamics", nullptr);
  const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
  std::vector<char> pinned(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (const PositionConstraint& pin : pins) {
    pinned[static_cast<std::size_t>(pin.vertex)] = 1;
  }
  std::vector<int> highest;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (pinned[static_cast<std::size_t>(v)] == 0) {
      highest.push_back(v);
    }
  }
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  std::partial_sort(highest.begin(), highest.begin() + 24, highest.end(),
                    [&](int a, int b) { return rest(2, a) > rest(2, b); });
  highest.resize(24);
  std::vector<PositionConstraint> constraints;
  int step_count = 0;
  const auto input = [&] {
    constraints = pins;
    if (holds != Holds::kPinned) {
      const int first = step_count % 8;
      for (int k = first; k < first + 16; ++k) {
        const int v = highest[static_cast<std::size_t>(k)];
        const Eigen::Vector3d target = rest.col(v) - Eigen::Vector3d(0.0, 0.0, 1e-3);
        if (holds == Holds::kContact) {
          constraints.push_back({v, target, kExact,
                                 PositionConstraint::along(Eigen::Vector3d::UnitZ()),
                                 /*anchors=*/false});
        } else {
          constraints.push_back({v, target, kExact});
        }
      }
    }
    ++step_count;
    return bench::liver_input(constraints);
  };
  const auto step = [&] { return body->step(kDt, input()); };
  if (!bench::time_steps(state, kWarmUpSteps, kStepsPerBatch, step, step)) {
    return;
  }
}

void register_benchmarks() {
  for (const auto& [label, holds] : {std::pair{"pinned", Holds::kPinned},
                                     std::pair{"contact", Holds::kContact},
                                     std::pair{"contact_refactorised", Holds::kContactRefactorised}}) {
    benchmark::RegisterBenchmark(
        (std::string("BM_ProjectiveDynamicsHolds/") + label + "/liver.msh").c_str(),
        [holds](benchmark::State& state) { holds_step(state, holds); })
        ->Unit(benchmark::kMillisecond);
  }
  for (const char* liver : kLivers) {
    for (const Variant& variant : variants()) {
      benchmark::RegisterBenchmark(
          ("BM_ProjectiveDynamicsStep/" + variant.label + "/" + liver).c_str(),
          [variant, liver](benchmark::State& state) {
            model_step(state, liver, "projective_dynamics", variant.params);
            // On liver_x16 the converged run (300 iterations a step) would take minutes.
            if (std::string(liver) != "liver_x16.msh") {
              state.counters["error_vs_converged"] = error_vs_converged(liver, variant);
            }
          })
          ->Unit(benchmark::kMillisecond);
    }
    benchmark::RegisterBenchmark(
        (std::string("BM_ProjectiveDynamicsStep/corotational_fem/") + liver).c_str(),
        [liver](benchmark::State& state) {
          model_step(state, liver, "corotational_fem", nlohmann::json::object());
        })
        ->Unit(benchmark::kMillisecond);
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
