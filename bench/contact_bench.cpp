// SPDX-License-Identifier: MIT
// The instrument contact's work per step (collision/instrument_contact.h: the trees' refits, the
// nearest-point queries, the triangle-pair count, the active set's corrections) on the shipped
// liver scenes, with a model deforming the liver under the probe:
//
//   BM_Contact/<scene>/<model>
//
// <model>: corotational_fem and shape_matching as the scene configures them, and
// shape_matching:thesis_one_pass (the scene's block stepped as the thesis stepped it: one pass,
// no volume correction).
//
// One iteration is the whole scene (300 steps at dt 1/60) driven as `softbench run` drives it
// (harness SceneStepper: the fixed region, the probe's path, every contact pass), on one thread.
// A step's contact work is the thread CPU time of the whole step less the model's (all its
// passes, on the same clock): what the contact adds to the model's step. The reported time
// (manual) is its mean per step over the scene.
//
// Counters, per step, CPU time:
// - contact_ms_touching: median over the steps that end with the tool loaded (a force on it:
//   the probe pressing, the grasp pulling), the contact's working level; contact_ms_apart: median
//   over the others (the probe on its way, the liver settling), where the work should be next
//   to nothing whatever the mesh; contact_ms_max: the worst step; measures_ms_touching: the
//   median over the touching steps of what is measured after the step, outside its timed work
//   (SceneStepper::observe: the thesis's triangle-pair count, the penetration, whether a step
//   that ran out of passes had settled), which the physics does not use;
// - model_ms: the model's median step (all passes); steps_per_s_with_contact: steps over the
//   summed CPU time of model and contact;
// - steps_touching, max_triangle_pairs (the thesis's measure of contact, table 4.2);
// - mean_iterations, iterations_touching (the models that solve linear systems): the solver's
//   iterations a solve over every pass of every step, and over the touching steps, where
//   corotational_fem's solves take twice those of the free steps;
// - what the contact bought, beside what it cost: peak_tool_force_N (the largest force on the
//   tool at any step) and max_penetration_mm (the deepest the tool went into the tissue, or the
//   tissue into the tool, at any step's end), as softbench run reports them;
// - what the figures did not finish, as softbench run counts it: unsettled_contact_steps (steps
//   that ran out of the scene's contact passes with the holds still changing; judged after the
//   step, outside its timed work) and truncated_solves (solves stopped at their iteration cap),
//   per scene;
// - force_vs_cholmod (corotational_fem): the largest difference at any step between its tool
//   force and that of the same scene with its solves by CHOLMOD (solver "cholmod"), relative
//   to that run's peak: what the default solver's stopping rule costs the contact's answer.
//   The exact run is stepped once per scene in a process, untimed.
//
// Run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true and quote medians;
// the machine is shared and noisy.
//
// Measured (2026-11-28, the 2-core EPYC VM, one thread; three runs of each build alternated,
// medians; "before" is the contact as it was before it skipped out-of-reach steps, bounded its
// searches and made its normals per query, with this benchmark; the results are bit for bit the
// same), contact ms per step:
//
//   scene / model            mean          touching      apart         worst
//   press / corotational_fem 0.339 -> 0.174 0.549 -> 0.393 0.167 -> 0.032 3.89 -> 2.49
//   press / shape_matching   1.646 -> 0.831 2.797 -> 2.327 0.184 -> 0.022 55.6 -> 41.0
//   pull / corotational_fem  0.221 -> 0.091 0.409 -> 0.303 0.164 -> 0.034 0.82 -> 0.51
//   pull / shape_matching    0.126 -> 0.023 0.113 -> 0.020 0.114 -> 0.020 0.32 -> 0.11
//
// (the model's step beside it: corotational_fem 2.1-2.4 ms, shape_matching 0.4-0.55 ms). In
// instructions (callgrind, the contact's functions over the press scene): 740 M -> 336 M with
// corotational_fem, 3.56 G -> 1.53 G with shape matching, 81% of it nearest-point searches of
// the probe's points near the tissue, over up to 32 passes a step where shape matching folds
// under the tip.
//
// Each such search then started at the triangle the point's last search found (2026-11-28,
// three runs of each build alternated, medians of their medians): press / shape_matching mean
// 0.895 -> 0.601 ms, touching 2.18 -> 1.75 ms (26.5 -> 16.4 nodes and 12.2 -> 6.7 triangle tests
// a search); press / corotational_fem 0.195 -> 0.196 ms, pull / corotational_fem 0.092 -> 0.092
// ms (unchanged: its searches were few and short); the peak tool forces the same to 1e-4.
// And then each point's clearance was spent by the tissue's and the tool's moves relative to the
// tool's own shift, not by their sum (two runs of each alternated with the code before both
// changes): press / shape_matching mean 0.756-0.788 -> 0.460-0.462 ms, press / corotational_fem
// 0.156-0.164 -> 0.146-0.154 ms (touching 0.41-0.42 -> 0.32-0.35), pull / corotational_fem
// 0.087-0.089 -> 0.068-0.071 ms; compare's contact, solver and shape figures the same as the
// code before both, to the last digit.
//
// Shape matching stepped as the thesis stepped it (2026-12-02, medians of 3): its step is 0.067
// ms on press (0.26 with the scene's four passes) and the contact about the same as with four
// passes (mean 0.49 ms, touching 1.70, worst 5.5): 1,720 steps/s with contact. On pull the one
// pass lets the liver crumple around the grasp: mean 59.8 ms a step, touching 22.5, worst 206
// ms, 605 triangle pairs (the scene's four passes: 0.018 ms, none). 78% of it was the
// refinement passes' nearest-point searches of the probe's points in and around the crumpled
// tissue (hold_tissue_around_points): about 2,800 of its 4,226 points a pass, on ~9.5 passes a
// step, 91% of them found outside within 3 mm (the tissue wrapped around the shaft; each pass
// moves it ~3 mm, so no clearance survives from one pass to the next).
//
// The probe's points were then made as collision/instrument_samples.h makes them (every vertex,
// the grid thinned to 0.43 spacings: 900 points instead of 4,226 at the same cover). Three runs
// of each build alternated, medians of their medians, contact ms per step, before -> after:
//
//   scene / model                     mean            touching        worst
//   press / corotational_fem          0.152 -> 0.090  0.360 -> 0.250  1.67-1.98 -> 0.90-1.00
//   press / shape_matching            0.445 -> 0.206  1.21 -> 0.762   10.7-13.0 -> 2.8-3.1
//   press / shape_matching one pass   0.564 -> 0.232  1.99 -> 0.795   5.2-7.0 -> 1.8-2.3
//   pull / corotational_fem           0.064 -> 0.055  0.180 -> 0.160  0.48-0.59 -> 0.33-0.39
//   pull / shape_matching             0.018 -> 0.017  0.018 -> 0.017  0.10-0.13 -> 0.08-0.09
//   pull / shape_matching one pass    61.5 -> 15.1    24.5 -> 11.7    222-265 -> 44-52
//
// (the model's step beside it: corotational_fem 1.0-1.4 ms, the VM's speed moving between
// runs). softbench run, with the FEM's liver on one thread as well (fem_bench): corotational_fem's
// tool force within 0.002% of its peak at every step of liver_press (peak 0.4271 N both; 0.4285
// N with the grid of step spacing / 4 unthinned) and 0.0005% on liver_pull, shape matching's
// on liver_pull bit for bit the same. Shape matching's force is spiky and its peak hangs on which
// points touch first: 1.20 N before, 1.51 N after, 1.35 N with the unthinned grid (its force
// curve 26% RMS from the unthinned grid's before, 27% after; its mean 0.153 / 0.151 / 0.164 N).
// The pull in one pass is bounded by the contact passes' cap and the points: at most 32 passes of
// 900 searches (about 2 us each where the tissue wraps the shaft), some 60 ms; it is that
// crumpling, not the contact, that costs.
//
// 2026-12-03, the FEM's step faster (fem_bench), medians of 3, each change against the build
// before it in the same minutes: steps_per_s_with_contact on liver_press / liver_pull 797 / 852
// -> 858 / 867 with no OpenMP construct on one range, then 875 / 923 -> 909 / 1,017 with the
// sweeps' gathers in lanes (model_ms 0.97 / 0.98 -> 0.94 / 0.89); tool forces the same to every
// digit (force_vs_cholmod 0.0047% / 0.00093%, peaks 0.4271 / 6.337 N).
//
// 2026-12-03, later: where corotational_fem's press costs beyond its liver step. Per step, one
// run: the contact is 8% of the step's time (0.08 of 1.1 ms on average), the model the rest,
// and the model's steps while touching cost more because its solves take twice the
// iterations: 9.2 a step against 4.3-4.8 apart (4 is the stopping rule's least, kDelay). The
// warm start leaves an energy-norm error of about 1% of the step's velocity while touching
// against 0.06% apart: the held corners move with the probe and their response is new each
// step. Tried and dropped:
// - aggregates on the coarse level (coarse_vertices 256 / 128 / 64): touching iterations 9.0 /
//   8.7 / 8.4, no time saved;
// - the warm start combining the free unknowns only, the known ones kept at the guess's values
//   (an identity row weighs a mismatch a thousandfold a free row's, which holds the combination
//   near the guess where the contact changes what is known): touching iterations 9.22 -> 8.98
//   on liver_press (all its steps 5.93 -> 5.89), but fem_bench's pinned liver 4.49 -> 4.67 a
//   step, the goal's own workload.
// Then the start of a step's contact in one pass over the tissue (four before) and
// corotational_fem's forces mapped to the mesh's numbering at the constrained vertices only,
// once a step (at every read before, into a new matrix): the same results to the digit; the
// time within the VM's noise this day (liver_pull touching 0.148-0.170 ms before, 0.156-0.166
// after, three runs of each build alternated).
//
// 2026-12-07: what a cap on the contact's passes (the scene's instrument.contact_passes) buys
// and costs, one run each, the scenes' files with only that key changed. Per cap: touching
// contact ms, worst step ms, steps/s with contact, unsettled steps, deepest penetration mm.
//
//   scene / model              cap  touching  worst  steps/s  unsettled  penetration
//   press / corotational_fem    32     0.214   0.74    1,061          0            0
//                                4     0.193   0.64    1,144          0            0
//                                2     0.185   0.59    1,141          0            0
//                                1     0.148   0.44    1,108          6         3.28
//   pull / corotational_fem     32     0.120   0.23    1,157          0            0
//                                4     0.114   0.22    1,148          0            0
//                                2     0.115   0.22    1,171          0            0
//                                1     0.106   0.17    1,153          3            0
//   press / shape matching*     32     0.623   1.56    4,144          0            0
//                                4     0.571   1.08    4,496          1         0.92
//                                2     0.519   0.74    4,979         34         3.62
//                                1     0.378   0.51    6,435         42         17.3
//   pull / shape matching*      32      6.05   38.6       83         97         5.80
//                                4      4.10   4.99      264        262         4.73
//                                2      2.00   3.42      450        291         7.93
//                                1      1.12   1.63      964        291         28.8
//
// (* the thesis's one-pass step.) The FEM's contact settles within two passes on both scenes:
// with 2 it is the default's to the digit (tool force against CHOLMOD's 0.0047% / 0.00093%),
// and only one pass leaves steps unsettled and the tissue 3.3 mm into the tool. Shape matching's
// crumpling pull settles in no budget: fewer passes trade its worst step (38.6 -> 1.6 ms) for
// penetration (5.8 -> 28.8 mm), 291 of its 300 steps unsettled with two passes or one.
//
// 2026-12-07, where the FEM press's contact work goes, in instructions (callgrind over
// InstrumentContact::resolve and refine, `softbench run scenes/liver_press.json --model
// corotational_fem`; the VM's timings moved by 2x that day): 185 M over the scene. The probe's
// points' nearest-point searches take 42% (about 20,000 a run, 3,800 instructions each: 13.7
// nodes, 2.9 leaves of up to 10 triangles, 5.8 point-triangle tests), the triangle-pair count
// (the thesis's measure: broad phase and exact tests) 19%, the tissue vertices' and free
// flight's queries 7%, the pass over the tissue that starts a step 8%, the trees' refits 6%.
// Of the searches at the step's start, 34% find the point 4 mm or more outside and 60% more than
// 1 mm: the clearances run out because the tool moves 1 mm a step while it presses, and the
// tissue at the dimple's rim stays put, so no bound that spends the relative motion keeps them.
// Tried and not kept:
// - searching a point still known to be outside only within the band's reach (2 margins plus the
//   tissue's free flight) instead of the fold's radius: each search opens fewer nodes, but the
//   "outside by the reach" it leaves runs out the next step where a full search's distance
//   lasted several: 3% more instructions over the scene, peak forces and penetration the same;
// - the tissue tree with leaves of 4, 6 or 2 triangles (13, 12 or 14 box levels instead of the
//   thesis's 11 of sphere and box): contact_ms_touching 0.25-0.28 ms against 0.23-0.24, the
//   refits and the pair count costing more than the searches save;
// - the start pass as whole-matrix Eigen passes: 25% more instructions than the one loop.
//
// 2026-12-07, later: two tighter clearance bounds (collision/sample_clearance.h), to spare the
// probe's points more searches. Counted with callgrind over `softbench run` (liver_press, the
// contact's resolve and refine for the FEM; every step's work for the thesis's one-pass shape
// matching); the results were the same to the digit in both. Neither kept:
// - spent by region: the surface's triangles in up to 64 groups compact at rest, each spending
//   only its own corners' largest move, and a query noting which groups' boxes lay within a
//   horizon beyond its distance. A contact pass of shape matching moves one vertex 3 mm and the
//   99th percentile 0.03 mm, yet the searches fell only 84,650 -> 72,000 (a horizon of one to
//   four sample spacings; 80,800 at sixteen): the points searched are those under the tip,
//   beside the patch that moves. Noting the groups cost 1,700 instructions a query, so the
//   scene took 922 M instructions against 789 M;
// - moves straight from the last four states as well as summed state by state (the tool moves
//   1 mm at a step's start with the tissue still, then the tissue catches up with the tool
//   still, and the sum spends both): searches 84,650 -> 80,100 with shape matching and 20,428
//   -> 19,465 with the FEM, while the extra passes over the tissue took the FEM's contact from
//   185 M to 200 M instructions.
// The points searched are, nearly all, points really within reach of the surface.
//
// 2026-12-08: the thesis's triangle-pair count left the step. It is a measure (no hold uses it),
// and it was a third of the contact's timed work: the instrument tree's refit, the broad phase
// and the exact tests ran inside resolve() every searched step. It is now counted after the
// step (InstrumentContact::count_triangle_pairs(), from SceneStepper::observe, with the
// penetration), on the same tissue and tool positions, so the counts are the same
// (max_triangle_pairs 72 / 62 with corotational_fem on press / pull, 92 / 442 with the one-pass
// shape matching), as is every other metric of `softbench run` on both scenes. Its cost shows
// in measures_ms_touching. Callgrind over resolve and refine in this benchmark's press /
// corotational_fem (the default run and the CHOLMOD one): 203.1 M -> 125.5 M instructions.
// Timed, the old and new builds alternated in the same minutes (medians of 3, contact ms
// touching): press / corotational_fem 0.336 -> 0.245, pull / corotational_fem 0.213 -> 0.179,
// press / shape_matching one pass 0.944 -> 0.823, pull / shape_matching one pass 9.24 -> 8.64
// (the crumpling pull's cost is its passes' searches, untouched).
#include "bench/bench_smoke.h"
#include "bench/thread_cpu_clock.h"
#include "harness/run/scene_mesh.h"
#include "harness/run/scene_stepper.h"
#include "models/model_registry.h"
#include "scenes/scene.h"
#include "scenes/shipped_data.h"

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace softbench {
namespace {

constexpr const char* kScenes[] = {"liver_press", "liver_pull"};

/// A model as the scene configures it, or with some of its parameters overridden.
struct ContactModel {
  std::string label;  ///< the benchmark name's model part
  std::string model;  ///< registry key
  nlohmann::json overrides = nlohmann::json::object();
  /// The overrides that make the same model exact (its linear solves by CHOLMOD), for
  /// force_vs_cholmod; null: the model has no exact setting.
  nlohmann::json exact = nullptr;
};

std::vector<ContactModel> contact_models() {
  return {
      {"corotational_fem", "corotational_fem", nlohmann::json::object(), {{"solver", "cholmod"}}},
      {"shape_matching", "shape_matching"},
      // Shape matching stepped as the thesis stepped it: one match and pull a step, no
      // volume correction (the scene's block keeps the defaults' four passes).
      {"shape_matching:thesis_one_pass",
       "shape_matching",
       {{"iterations", 1}, {"preserve_volume", false}}}};
}

std::unique_ptr<SoftBody> make_body(const scenes::Scene& scene,
                                    const harness::SceneMesh& mesh,
                                    const std::string& model_name,
                                    const nlohmann::json& overrides) {
  nlohmann::json parameters = scene.parameters_for(model_name);
  if (parameters.is_null()) {
    parameters = nlohmann::json::object();
  }
  parameters.update(overrides);
  return builtin_models()
      .at(model_name)
      .create(mesh.body, scene.material, parameters,
              {scene.source.string(), "/models/" + model_name});
}

/// N: the tool's force after each of the first `steps` steps of the scene with the model made
/// exact (ContactModel::exact), once per scene, model and step count in a process.
const std::vector<double>& exact_tool_forces(const scenes::Scene& scene,
                                             const harness::SceneMesh& mesh,
                                             const ContactModel& variant,
                                             int steps) {
  static std::map<std::string, std::vector<double>> cache;
  const std::string key = scene.name + "/" + variant.label + "/" + std::to_string(steps);
  const auto found = cache.find(key);
  if (found != cache.end()) {
    return found->second;
  }
  nlohmann::json overrides = variant.overrides;
  overrides.update(variant.exact);
  std::unique_ptr<SoftBody> body = make_body(scene, mesh, variant.model, overrides);
  harness::SceneStepper stepper(scene, mesh);
  stepper.start(*body);
  std::vector<double> forces;
  for (int step = 0; step < steps; ++step) {
    stepper.step(step, *body);
    stepper.observe(step, *body);
    forces.push_back(stepper.loading().tool_force());
  }
  return cache.emplace(key, std::move(forces)).first->second;
}

/// The largest difference at any step between two tool-force histories, relative to the
/// reference's peak (0 when it never touches).
double force_error(const std::vector<double>& forces, const std::vector<double>& reference) {
  double peak = 0.0;
  double largest = 0.0;
  for (std::size_t k = 0; k < reference.size() && k < forces.size(); ++k) {
    peak = std::max(peak, reference[k]);
    largest = std::max(largest, std::abs(forces[k] - reference[k]));
  }
  return peak > 0.0 ? largest / peak : 0.0;
}

double median(std::vector<double> values) {
  if (values.empty()) {
    return 0.0;
  }
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

double thread_cpu_seconds() {
  return bench::thread_cpu_us() * 1e-6;
}

void contact_benchmark(benchmark::State& state,
                       const std::string& scene_name,
                       const ContactModel& variant) {
  const std::string& model_name = variant.model;
  omp_set_num_threads(1);
  const scenes::Scene scene =
      scenes::load_scene(scenes::shipped_data_dir().parent_path() / (scene_name + ".json"));
  const harness::SceneMesh mesh = harness::read_scene_mesh(scene);
  const int steps = bench::unless_smoke(scene.num_steps(), 20);

  std::vector<double> touching, apart, model, measures_touching;
  // Linear-solver iterations and solves (all passes), over every step and the touching ones.
  long iterations = 0, solves = 0, touching_iterations = 0, touching_solves = 0;
  long unsettled = 0, truncated = 0;
  double contact_total = 0.0, model_total = 0.0;
  long stepped = 0;
  int max_pairs = 0;
  double max_penetration = 0.0;
  // The tool's force after each step of the last iteration (every iteration steps the same).
  std::vector<double> forces;
  for (auto _ : state) {
    state.PauseTiming();
    std::unique_ptr<SoftBody> body = make_body(scene, mesh, model_name, variant.overrides);
    forces.clear();
    harness::SceneStepper stepper(scene, mesh);
    stepper.start(*body);
    state.ResumeTiming();
    double iteration_contact = 0.0;
    for (int step = 0; step < steps; ++step) {
      double model_seconds = 0.0;
      const double before = thread_cpu_seconds();
      const StepStats stats = stepper.step(step, *body, &model_seconds, thread_cpu_seconds);
      const double stepped_at = thread_cpu_seconds();
      const double contact_seconds = stepped_at - before - model_seconds;
      stepper.observe(step, *body);
      const double measure_seconds = thread_cpu_seconds() - stepped_at;
      if (!stats.finite) {
        state.SkipWithError((model_name + " diverged on " + scene_name).c_str());
        return;
      }
      const bool loaded = stepper.loading().tool_force() > 0.0;
      (loaded ? touching : apart).push_back(1e3 * contact_seconds);
      if (loaded) {
        measures_touching.push_back(1e3 * measure_seconds);
      }
      iterations += stats.iterations;
      solves += stats.linear_solves;
      truncated += stats.truncated_solves;
      if (loaded) {
        touching_iterations += stats.iterations;
        touching_solves += stats.linear_solves;
      }
      forces.push_back(stepper.loading().tool_force());
      model.push_back(1e3 * model_seconds);
      iteration_contact += contact_seconds;
      model_total += model_seconds;
      ++stepped;
    }
    contact_total += iteration_contact;
    unsettled += stepper.unsettled_contact_steps();
    max_pairs = std::max(max_pairs, stepper.loading().max_triangle_pairs());
    max_penetration = std::max(max_penetration, stepper.loading().max_penetration());
    state.SetIterationTime(iteration_contact / steps);
  }
  state.counters["contact_ms_touching"] = median(touching);
  state.counters["contact_ms_apart"] = median(apart);
  state.counters["measures_ms_touching"] = median(measures_touching);
  std::vector<double> all = touching;
  all.insert(all.end(), apart.begin(), apart.end());
  state.counters["contact_ms_max"] = all.empty() ? 0.0 : *std::max_element(all.begin(), all.end());
  state.counters["model_ms"] = median(model);
  state.counters["steps_per_s_with_contact"] =
      static_cast<double>(stepped) / std::max(contact_total + model_total, 1e-300);
  state.counters["steps_touching"] =
      static_cast<double>(touching.size()) / static_cast<double>(state.iterations());
  state.counters["max_triangle_pairs"] = max_pairs;
  const auto per_scene = [&](long count) {
    return static_cast<double>(count) / static_cast<double>(state.iterations());
  };
  state.counters["unsettled_contact_steps"] = per_scene(unsettled);
  state.counters["truncated_solves"] = per_scene(truncated);
  if (solves > 0) {
    state.counters["mean_iterations"] =
        static_cast<double>(iterations) / static_cast<double>(solves);
    state.counters["iterations_touching"] =
        touching_solves > 0
            ? static_cast<double>(touching_iterations) / static_cast<double>(touching_solves)
            : 0.0;
  }
  state.counters["peak_tool_force_N"] =
      forces.empty() ? 0.0 : *std::max_element(forces.begin(), forces.end());
  state.counters["max_penetration_mm"] = 1e3 * max_penetration;
  if (!variant.exact.is_null()) {
    state.counters["force_vs_cholmod"] =
        force_error(forces, exact_tool_forces(scene, mesh, variant, steps));
  }
}

void register_benchmarks() {
  for (const char* scene : kScenes) {
    for (const ContactModel& model : contact_models()) {
      benchmark::RegisterBenchmark((std::string("BM_Contact/") + scene + "/" + model.label).c_str(),
                                   [scene = std::string(scene), model](benchmark::State& state) {
                                     contact_benchmark(state, scene, model);
                                   })
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime()
          ->Iterations(1);
    }
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
