// SPDX-License-Identifier: MIT
// Bullet's soft bodies against ours on the same mesh, in one process, so the ratios are taken
// under the same machine load:
//
//   BM_BulletStep/<variant>/<mesh>      one step at the variant's dt, over bench::timed_steps()
//   BM_LargestStableDt/<variant>/<mesh> the largest dt of a ladder that survives 1 s
//
// Setting: the liver_gravity scene (its material, gravity, fixed band and model blocks, so
// bullet_softbody runs with the stiffness `softbench calibrate` fitted) on liver.msh and its
// refinement liver_x4.msh, from rest. Our models run first (each registered model with the
// scene's block at the scene's dt; shape matching also as the thesis stepped it,
// shape_matching:thesis_one_pass), then the Bullet variants.
//
// Counters (per step unless stated):
// - steps_per_s (rate), mean_iterations (CG iterations for bullet_deformable and our implicit
//   models, position iterations for bullet_softbody), mean_linear_solves, dt_s;
// - Bullet variants: time_ratio_vs_<model> = this step's CPU time / <model>'s, for each of our
//   models measured earlier in the same process (> 1: Bullet is slower; CPU time of the whole
//   process, bench/thread_cpu_clock.h, so a descheduled thread does not skew the ratio);
// - BM_LargestStableDt: largest_stable_dt_s (0: none of the ladder), sim_s_per_cpu_s (simulated
//   seconds per CPU second at that dt), final_max_speed_m_per_s (the largest vertex speed over
//   the last tenth of the run: a run that stays bounded without settling, as Bullet's explicit
//   neo-Hookean at 1/30 s does, shows ~1 m/s here where a settling one shows ~0.01) and, for
//   Bullet variants, sim_time_ratio_vs_<model> = <model>'s sim_s_per_cpu_s / this one's (> 1:
//   Bullet needs more CPU time per simulated second).
// "Stable" is the harness's test: no NaN, no vertex faster than the scene's 50 m/s, none
// displaced more than 10 bounding-box diagonals, for 1 s of simulated time.
//
// The machine is shared and noisy: run with --benchmark_repetitions=3 and quote medians;
// OMP_WAIT_POLICY=passive as for step_bench. Bullet runs single-threaded.
#include "bench/bench_liver.h"
#include "bench/bench_smoke.h"
#include "bench/thread_cpu_clock.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "models/model_registry.h"
#include "scenes/scene.h"
#include "scenes/scene_regions.h"
#include "scenes/shipped_data.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace softbench {
namespace {

const char* const kLivers[] = {"liver.msh", "liver_x4.msh"};
constexpr int kWarmUpSteps = 10;
constexpr int kStepsPerBatch = 4;
/// s: each rung of the ladder is run this long.
constexpr double kStabilityTime = 1.0;
const double kDtLadder[] = {1.0 / 30.0,  1.0 / 60.0,   1.0 / 120.0, 1.0 / 250.0,
                            1.0 / 500.0, 1.0 / 1000.0, 1.0 / 2000.0};

struct Variant {
  std::string label;  ///< the benchmark name's model part
  std::string model;  ///< registry key
  nlohmann::json params;
  double dt = 0.0;  ///< 0: the scene's
  bool bullet = false;
};

const scenes::Scene& liver_scene() {
  static const scenes::Scene scene =
      scenes::load_scene(scenes::shipped_data_dir().parent_path() / "liver_gravity.json");
  return scene;
}

nlohmann::json scene_block(const std::string& model) {
  const auto block = liver_scene().model_parameters.find(model);
  return block == liver_scene().model_parameters.end() ? nlohmann::json(nullptr) : block->second;
}

bool is_bullet(const std::string& model) {
  return model.rfind("bullet_", 0) == 0;
}

/// Our models, then Bullet's: the step benchmarks at a fixed dt.
std::vector<Variant> step_variants() {
  std::vector<Variant> result;
  for (const std::string& name : builtin_models().default_names()) {
    if (!is_bullet(name)) {
      result.push_back({name, name, scene_block(name), 0.0, false});
    }
  }
  // Shape matching stepped as the thesis stepped it (its scene block, one match and pull a
  // step, no volume correction): the configuration the thesis's speed claims are about.
  nlohmann::json one_pass = scene_block("shape_matching");
  one_pass["iterations"] = 1;
  one_pass["preserve_volume"] = false;
  result.push_back({"shape_matching:thesis_one_pass", "shape_matching", one_pass, 0.0, false});
  for (const std::string& name : builtin_models().default_names()) {
    if (is_bullet(name)) {
      result.push_back({name, name, scene_block(name), 0.0, true});
    }
  }
  if (builtin_models().contains("bullet_deformable")) {
    // Bullet's own CG tolerance in the double build: every solve runs to its 300-iteration cap.
    result.push_back({"bullet_deformable:cg_tolerance=DBL_EPSILON",
                      "bullet_deformable",
                      {{"cg_tolerance", std::numeric_limits<double>::epsilon()}},
                      0.0,
                      true});
    result.push_back({"bullet_deformable:mass_spring",
                      "bullet_deformable",
                      {{"force", "mass_spring"}},
                      0.0,
                      true});
    // Symplectic Euler with Bullet's implicit damping: stable at the scene's dt on the liver.
    result.push_back({"bullet_deformable:explicit_neo_hookean",
                      "bullet_deformable",
                      {{"implicit", false}},
                      0.0,
                      true});
    result.push_back({"bullet_deformable:corotated@dt=1e-3",
                      "bullet_deformable",
                      {{"force", "corotated"}, {"implicit", false}},
                      1e-3,
                      true});
  }
  return result;
}

/// Every model configuration whose stability limit is asked for: the step variants that run at
/// the scene's dt (not the CG-tolerance one: the same scheme), plus Bullet's explicit ones.
std::vector<Variant> stability_variants() {
  std::vector<Variant> result;
  for (const Variant& variant : step_variants()) {
    if (variant.dt == 0.0 && variant.label.find('=') == std::string::npos) {
      result.push_back(variant);
    }
  }
  if (builtin_models().contains("bullet_deformable")) {
    result.push_back({"bullet_deformable:corotated",
                      "bullet_deformable",
                      {{"force", "corotated"}, {"implicit", false}},
                      0.0,
                      true});
    result.push_back({"bullet_deformable:explicit_mass_spring",
                      "bullet_deformable",
                      {{"force", "mass_spring"}, {"implicit", false}},
                      0.0,
                      true});
  }
  return result;
}

/// What our models measured, by mesh then label, for the Bullet variants' ratios.
std::map<std::string, std::map<std::string, double>>& our_step_seconds() {
  static std::map<std::string, std::map<std::string, double>> seconds;
  return seconds;
}
std::map<std::string, std::map<std::string, double>>& our_sim_rates() {
  static std::map<std::string, std::map<std::string, double>> rates;
  return rates;
}

struct Setting {
  std::unique_ptr<SoftBody> body;
  std::vector<PositionConstraint> pins;
  StepInput input;
};

Setting make_setting(const Variant& variant, const TetMesh& mesh) {
  const scenes::Scene& scene = liver_scene();
  Setting setting;
  setting.body = builtin_models()
                     .at(variant.model)
                     .create(mesh, scene.material, variant.params,
                             ParamSource{"bullet_bench", "/" + variant.label});
  for (int vertex : scenes::fixed_vertices(scene, mesh)) {
    setting.pins.push_back({vertex, mesh.rest_positions().col(vertex)});
  }
  setting.input.gravity = scene.gravity.acceleration;
  setting.input.constraints = setting.pins;
  return setting;
}

void step_benchmark(benchmark::State& state, const Variant& variant, const std::string& name) {
  const TetMesh& mesh = bench::shipped_liver(name);
  const double dt = variant.dt > 0.0 ? variant.dt : liver_scene().dt;
  Setting setting = make_setting(variant, mesh);
  for (int step = 0; step < bench::unless_smoke(kWarmUpSteps, 1); ++step) {
    setting.body->step(dt, setting.input);
  }
  bench::StepTotals totals;
  double seconds = 0.0;
  while (state.KeepRunningBatch(kStepsPerBatch)) {
    const double start = bench::process_cpu_seconds();
    for (int step = 0; step < kStepsPerBatch; ++step) {
      totals.add(setting.body->step(dt, setting.input));
    }
    seconds += bench::process_cpu_seconds() - start;
  }
  if (!totals.report(state)) {
    return;
  }
  const auto steps = static_cast<double>(state.iterations());
  state.counters["dt_s"] = dt;
  state.counters["vertices"] = mesh.num_vertices();
  const double step_seconds = seconds / steps;
  if (!variant.bullet) {
    our_step_seconds()[name][variant.label] = step_seconds;
    return;
  }
  for (const auto& [ours, ours_seconds] : our_step_seconds()[name]) {
    state.counters["time_ratio_vs_" + ours] = step_seconds / ours_seconds;
  }
}

/// Whether `variant` survives kStabilityTime at dt; its CPU seconds per step meanwhile, and the
/// largest vertex speed over the run's last tenth (a bounded run that never settles shows here).
bool survives(const Variant& variant,
              const TetMesh& mesh,
              double dt,
              double& step_seconds,
              double& final_speed) {
  Setting setting = make_setting(variant, mesh);
  const scenes::Scene& scene = liver_scene();
  const Eigen::Matrix<double, 3, 2> box = bounding_box(mesh.rest_positions());
  const double max_displacement = scene.limits.max_displacement * (box.col(1) - box.col(0)).norm();
  const int steps = bench::unless_smoke(static_cast<int>(std::ceil(kStabilityTime / dt)), 2);
  final_speed = 0.0;
  const double start = bench::process_cpu_seconds();
  for (int step = 0; step < steps; ++step) {
    const StepStats stats = setting.body->step(dt, setting.input);
    const Eigen::Matrix3Xd& x = setting.body->positions();
    const Eigen::Matrix3Xd& v = setting.body->velocities();
    const double speed = v.allFinite() ? v.colwise().norm().maxCoeff() : INFINITY;
    if (!stats.finite || !x.allFinite() || speed > scene.limits.max_speed
        || (x - mesh.rest_positions()).colwise().norm().maxCoeff() > max_displacement) {
      return false;
    }
    if (10 * step >= 9 * steps) {
      final_speed = std::max(final_speed, speed);
    }
  }
  step_seconds = (bench::process_cpu_seconds() - start) / steps;
  return true;
}

void stable_dt_benchmark(benchmark::State& state, const Variant& variant, const std::string& name) {
  const TetMesh& mesh = bench::shipped_liver(name);
  double largest = 0.0;
  double step_seconds = 0.0;
  double final_speed = 0.0;
  for (auto _ : state) {
    for (const double dt : kDtLadder) {
      if (survives(variant, mesh, dt, step_seconds, final_speed)) {
        largest = dt;
        break;
      }
    }
  }
  state.counters["largest_stable_dt_s"] = largest;
  state.counters["vertices"] = mesh.num_vertices();
  if (largest == 0.0) {
    return;
  }
  const double sim_rate = largest / step_seconds;  // simulated s per CPU s
  state.counters["sim_s_per_cpu_s"] = sim_rate;
  state.counters["final_max_speed_m_per_s"] = final_speed;
  if (!variant.bullet) {
    our_sim_rates()[name][variant.label] = sim_rate;
    return;
  }
  for (const auto& [ours, ours_rate] : our_sim_rates()[name]) {
    state.counters["sim_time_ratio_vs_" + ours] = ours_rate / sim_rate;
  }
}

void register_benchmarks() {
  for (const char* mesh_name : kLivers) {
    for (const Variant& variant : step_variants()) {
      benchmark::RegisterBenchmark(
          ("BM_BulletStep/" + variant.label + "/" + mesh_name).c_str(),
          [variant, mesh = std::string(mesh_name)](benchmark::State& state) {
            step_benchmark(state, variant, mesh);
          })
          ->Iterations(bench::timed_steps(bench::slow_model(variant.model), kStepsPerBatch))
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
  for (const char* mesh_name : kLivers) {
    for (const Variant& variant : stability_variants()) {
      benchmark::RegisterBenchmark(
          ("BM_LargestStableDt/" + variant.label + "/" + mesh_name).c_str(),
          [variant, mesh = std::string(mesh_name)](benchmark::State& state) {
            stable_dt_benchmark(state, variant, mesh);
          })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Iterations(1);
    }
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
