// SPDX-License-Identifier: MIT
// One step of the corotational FEM (models/corotational_fem/) on the shipped liver and its two
// refinements, per linear solver and thread count:
//
//   BM_FemStep/<variant>/<mesh>/threads:<T>
//
// Scene-like setting (as step_bench): E 3000 Pa, nu 0.3, 1060 kg/m^3, gravity -z, the vertices
// in the lowest 10% of the x extent pinned exactly, dt = 1/60 s, from rest. kWarmUpSteps steps
// first, then bench::kTimedSteps timed, the same steps on every mesh, thread count and machine: the
// liver sagging and swinging back (large rotations).
//
// Counters (per step unless stated):
// - steps_per_s (rate), mean_iterations (CG), mean_factorizations (numeric Cholesky);
// - elements_ms, assembly_ms, solve_ms, update_ms: the phases of the step, timed inside the
//   model with a steady clock (CorotationalFemModel::step_timed);
// - cholmod_match: after kMatchSteps steps from rest, RMS |x - x_cholmod| / RMS |x_cholmod - X|
//   against CHOLMOD with the same formulation and rotation (the solver's error relative to the
//   motion; the goal is < 0.01);
// - exact_match: the same against CHOLMOD with exact (SVD) rotations: the solver's and the
//   rotation method's error together.
//
// Variants: "cholmod", "cg", "cholesky_pcg" with the model's defaults on every mesh and thread
// count, and cg with what its defaults replaced: "cg+jacobi" (the Jacobi preconditioner),
// "cg+last_warm_start" (from the last solution alone) and both; on liver.msh with one thread
// also cg with other tolerances, rotation methods and the linear formulation (what the
// defaults trade).
//
// Threads: T is set with omp_set_num_threads inside the benchmark. The model parallelises from
// 2048 vertices (liver.msh, 1215, runs on one thread), each step on the threads or on one as
// ThreadChoice finds faster (models/thread_choice.h: on a shared 2-core machine a short region
// loses more to a descheduled thread than it gains). Both thread counts time the same steps
// (before 2026-12-07 the two-thread run took more steps in its half second, later and cheaper
// ones, and the ratio read the motion as well as the threads). CHOLMOD calls OpenBLAS, whose
// pthreads are separate (OPENBLAS_NUM_THREADS): run the CHOLMOD variants with
// OMP_WAIT_POLICY=passive (our idle OpenMP threads otherwise spin on the cores OpenBLAS needs:
// liver_x4 107 -> 82 ms), the CG variants with the default policy (passive makes every one of CG's
// short regions pay a wake-up: x4 with 2 threads 7.0 -> 16 ms). The machine is shared and noisy:
// run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true and quote medians.
//
// Results (2026-11-25, this 2-core Xeon VM, shared: a build ran beside it; medians of 5
// repetitions, real time), with the iterative solves stopping on the estimated energy-norm error
// of the new velocity (models/system_solver.h; cg's default tolerance 1e-3). ms per step,
// steps/s, mean iterations, and cholmod_match:
//
//   liver.msh (1215 v, 4777 tets)   1 thread
//   cholmod                         20.9 ms   48/s
//   cg (default)                    1.79 ms  559/s  17.5 it, match 0.051% (11.7x cholmod)
//   cholesky_pcg                    3.88 ms  258/s  7.7 it, 0.007 fact/step, match 0.002%
//   liver_x4.msh (4091 v, 22861)
//   cholmod                          110 ms  9.1/s
//   cg                              10.6 ms   94/s  30.7 it, match 0.067%
//   cholesky_pcg                    46.0 ms   22/s  8.4 it, 0.06 fact/step
//   liver_x16.msh (14562 v, 84530)
//   cholmod                          725 ms  1.4/s
//   cg                              85.1 ms   12/s  46.8 it, match 0.090%; 2 threads 41.5 ms
//   cholesky_pcg                     296 ms  3.4/s  11.3 it
//
// 2026-11-27 (the same VM, slower that day by the old default's figure, and a soak's core
// paused; one process, the four cg variants interleaved, 10 repetitions of 0.3 s, CPU-time
// medians): cg (the default: SSOR and the projected warm start) 4.17 ms at 7.0 iterations,
// cholmod_match 0.020%; cg+jacobi+last_warm_start (the default before) 4.15 ms at 21.2, 0.051%;
// cg+jacobi 3.65 ms at 13.6, 0.117%; cg+last_warm_start 4.17 ms at 11.1, 0.024%. An SSOR
// iteration costs about 2.5 Jacobi iterations (scalar gathers over half-columns, three 3x3
// products a vertex); the default buys 2.5x the accuracy at the same cost here, and under
// contact it is the faster (liver_press: 2.7 vs 3.1 ms median step, force within 0.005% RMS of
// CHOLMOD's against 0.03%).
//
// The larger livers the same day (interleaved, medians of 3, real time; cholmod_match in %):
//                    1 thread              2 threads
//   liver_x4   cg    16.9 ms  10.3 it 0.038  10.3 ms  9.9 it
//              jacobi 14.0 ms 22.0 it 0.126  10.7 ms
//   liver_x16  cg    133 ms   15.0 it 0.040   123 ms (1.09x)
//              jacobi 145 ms  33.0 it 0.137   103 ms (1.41x)
// The SSOR solve then ran on one thread, so with two threads on liver_x16 Jacobi's parallel
// products won by 16%, at 3.4x the error; with one thread SSOR won everywhere but liver_x4.
// The default stays SSOR at every size: a choice by thread count would make a run's bits
// depend on it, and both meet the 1% goal ("jacobi" is the faster on many cores).
//
// 2026-11-28: from 2048 vertices the model numbers the mesh in two parts and a separator and
// the SSOR sweeps run the parts side by side (ssor_solver.h). cg, medians of 3, real time, the
// two thread counts in the same process (the VM's speed moved by 1.5x between runs, so only
// the same run's ratio is quoted); two threads against one:
//                 before (one-thread sweeps)   after
//   liver_x4      1.41x, 1.46x                 1.85x, 1.83x
//   liver_x16     1.56x, 1.25x                 1.85x, 2.7x (solve 66.6 -> 23.3 ms)
// The separator, swept after both parts, couples later: 14.0-15.0 iterations on liver_x16
// (13.9-15.0 before), cholmod_match 0.042% (0.035%), liver_x4 0.028% (0.024%). liver.msh is
// one part, its results unchanged to the last digit. Under a busy second core (a spinning
// process) two threads lose, as they did before: every parallel region waits for the thread the
// scheduler has set aside. liver_x4 one / two threads 6.5 / 14.7 ms before, 7.2 / 22.0 after;
// liver_x16 76 / 83 before, 45 / 101 after (the sweeps add two regions an iteration). The
// results do not depend on the thread count, so the model now chooses it step by step from
// what each way took (models/thread_choice.h): under the busy core 64.7 / 65.1 ms, idle 77.0 /
// 43.7 (1.76x; a step in 16 tries one thread).
//
// 2026-11-28: the assembly's gathers prefetch the element terms eight incidences ahead, and a
// block's place in the matrix is two ints (BlockEntries). 600 steps of the liver's sag, whole
// processes alternated 12 times with the code before, one thread: 0.94x CPU time (0.77-1.05;
// the prefetch alone 0.93-0.96), the same iterations (4.74 a step) and positions to 12 digits.
// Where the step goes now (perf): the SSOR solve 29%, its products besides (the warm start's
// 8%, the translation sums 2.7%, the stopping rule's reference energy 2.5%, the diagonal 1.8%),
// assembly 21%, element terms 15%, rotations 12%. Element terms computed eight elements to a
// batch of lanes (as the rotations are) did not vectorise under GCC 12 and took more
// instructions (4.0 M a step against 2.6 M): not kept.
//
// 2026-11-28, later: the gathers sum outer products four doubles at a time and no longer
// prefetch (with the renumbered vertices the prefetch cost 7%), F and R are made in the element
// kernel's lanes from rest data kept in lane layout, the solve starts from the warm start's own
// product (one sweep fewer), the reference energy is a quadratic form over half the matrix, the
// four-vector product loads its lanes directly, and SSOR's backward sweep adds its newest
// neighbour last. The sag alternated with the code before, one thread: 0.77x (liver, 20 pairs),
// 0.71x (liver_x4, 6), 0.75x (liver_x16, 3); iterations and positions the same to 12 digits.
// Where the liver's step goes now (perf): the SSOR solve 30%, the warm start's products 6%, the
// diagonal and translation sums 5%, the reference energy 2.6%; the gathers 22%; the element
// kernels 25% (terms 9.5%, rotations 7%, F 4.4%).
//
// 2026-11-28, last: from 1024 vertices (so the shipped liver too) the mesh is numbered in two
// parts and every loop may run parallel; ThreadChoice probes the other way four steps at a time,
// as often as costs 1% of the time, and probes the threads only while a core is free. cg,
// medians of 3, real time, the two thread counts in the same process:
//                 1 thread              2 threads
//   liver        1.61 ms  4.97 it      0.99 ms  4.59 it   1.63x  cholmod_match 0.017% (0.015%
//                                                                  as one part)
//   liver_x4     7.23 ms  9.13 it      4.87 ms  8.64 it   1.48x  0.028%
//   liver_x16    70.1 ms  13.9 it      46.4 ms  15.0 it   1.51x  0.042%
// (the runs' iteration counts differ as their lengths do: two threads run more steps in the
// time, nearer rest). Under a busy second core the liver took 1.22 / 1.20 ms on one / two
// threads: no step of the second ran on the threads.
//
// 2026-12-02: the one-thread step had come down to 1.0 ms on the liver, and two threads no longer
// won there (same process, two builds alternated, medians of 5): from 1024 vertices 1.00 /
// 1.04 ms on one thread, 1.09 / 1.05 on two; from 2048 (the liver on one thread, as one part)
// 1.00 / 1.02 and 1.00 / 0.99, cholmod_match 0.0173% -> 0.0146%, 4.56 iterations either way.
// The bound is 2048 since: liver_x4 and liver_x16 run as before.
//
// 2026-12-02, later: the SSOR solve is deflated by a coarse level, the translations of
// aggregates of vertices (models/coarse_space.h), of 64 vertices from 2048 (the default; the
// variants cg+coarse_32, cg+coarse_128 and cg+coarse_whole_body, the whole body one aggregate,
// which is the default below 2048 and what every mesh ran before). One thread, real-time
// medians, ms a step, iterations, cholmod_match in %:
//                 whole body             aggregates of 64        32                 128
//   liver         1.17  4.70 it 0.013    1.28  4.50 it 0.0008   1.29  4.44 it      1.16  4.51 it
//   liver_x4      5.76  8.70 it 0.024    5.71  6.56 it 0.0009   6.67  6.40 it      7.48  7.30 it
//   liver_x16     53.2  14.4 it 0.041    40.6  8.65 it 0.0020   60.4  7.75 it      46.8  9.44 it
// (one run, in order, on a VM whose speed moved by 1.4x within it), and liver_x16 alone with the
// variants interleaved (5-6 repetitions): whole body 48.0 ms / 14.8 it, 64 42.0 / 8.7, 128
// 42.5 / 9.5; after (A W)^T s moved into the backward sweep, in a slow phase of the VM, whole body
// / 64: one thread 57.8 / 55.4 ms, two 35.0 / 31.6 (1.65x / 1.75x). The iterations no longer
// grow as they did (4.7 -> 14.4 over 15x the tets, now 4.5 -> 8.7), and every error against
// CHOLMOD fell 10-25 fold; the time gained is less than the iterations saved: E (684 unknowns on
// liver_x16) is factorised every step (about 2 ms), and each iteration adds a coarse solve and
// two passes over A W's blocks (2-3 aggregates a vertex) to its two sweeps.
//
// 2026-12-02, last: the coarse level's A W and U W blocks are summed by runs of slots in
// registers (each solve's load had cost about an iteration), and E's factor is supernodal from
// 256 unknowns (liver_x16's 684; simplicial below, the liver's 3 and liver_x4's ~190). In
// instructions (callgrind, contact_bench's liver_press with corotational_fem, 300 steps): the
// loads 419 M -> 208 M, the FEM's steps 3.88 G -> 3.69 G (5%), the peak tool force 0.427086 ->
// 0.427087 N (the sums' new order); E's factorisation halved at 648 unknowns, its solves no
// dearer. Liver, one thread, the two builds alternated five times (3 repetitions each): 1.25
// -> 1.19 ms (medians; pair by pair 0.84-1.02, median 0.95), solve 0.78 -> 0.73 ms. liver_x16
// did not settle on this VM that day: one thread 55.7 ms before and 61.8 after in runs minutes
// apart, two threads 33.4 and 42.7, the same code 40-82 ms an hour earlier.
//
// 2026-12-03: the loops over vertex ranges (over_ranges(), eisenstat_cg.h) run as a plain loop
// when one range has vertices, the liver's case: a region serial by its if clause had still paid
// libgomp's team and dynamic schedule about fifty times a step. Liver, one thread, builds
// alternated three times (medians of 5): 955 -> 1,082 steps/s (1.05 -> 0.92 ms). Then
// BlockPattern::neighbour_sum (the sweeps' and the quadratic form's gathers) multiplies a
// neighbour's block in three four-lane multiply-adds, one per column strip, each lane the scalar
// loop's sum in its order: five alternations, solve 0.577 -> 0.525 ms, 1,011 -> 1,068 steps/s;
// liver_x16 one thread about 1.1x (26-28 -> 29.8 steps/s; the VM's speed moved by 1.5x within
// the hour), two threads the same (35 steps/s: the two-thread solve is bound by the memory both
// cores share). cholmod_match unchanged to its last digit (0.0132%): the same iterates. Summing
// even and odd neighbours apart (two chains) gained nothing further; nor did the SSOR blocks'
// 3x3 products in lanes.
//
// 2026-12-07: where liver_x16's step went (one thread, timers around the solver's parts): E's
// load and factorisation 7.7 ms a solve, the coarse solves 0.9 ms, the sweeps the rest of a
// 45.6 ms solve at 8.6 iterations, 4.3 ms an iteration, 300 ns a vertex against the liver's
// 120: its matrix (about 16 MB, read once an iteration with A W's blocks, another 5 MB) is
// streamed from memory where the liver's (1.3 MB) stays in the cache. The sweeps then read a
// single-precision copy of the values from 2048 vertices (sweep_precision; the variants
// cg+double_sweeps and cg+single_sweeps at every size). One thread, the two variants interleaved
// in one process, medians of 5, ms a step (the solve), iterations, cholmod_match:
//                 double                         single
//   liver         0.970 (0.552)  4.50 it 0.0132% 0.963 (0.539)  4.49 it 0.0132%
//   liver_x4      6.40  (4.16)   6.75 it         6.28  (4.11)   6.61 it 0.00092% both
//   liver_x16     55.1  (42.4)   8.56 it         37.4  (26.4)   8.65 it 0.00204% both
// (the runs' iteration counts differ as their lengths do). The default's figure on the liver
// is the double one: below 2048 vertices nothing changed.
//
// 2026-12-07, later, the same VM, timers around the solve's parts again (one thread, liver_x16,
// ms a solve): the 7.7 ms above held waits. Debian's CHOLMOD factorises a large supernode
// (E there: 684 unknowns, one supernode) with OpenMP regions of four threads of its own, which
// no omp_set_num_threads() bounds: three threads beyond the caller's on the 2-core machine, at
// every factorisation, one thread or two (perf: futex waits 8% of the step's samples, the extra
// threads' spinning 5% of its CPU; the benchmark's real time 1-2 ms above its thread CPU time).
// CholmodFactor now runs CHOLMOD with no OpenMP level active. After: E's factorisation 1.33,
// its blocks 2.2, the diagonal blocks 1.35, the single-precision copy 0.83, the start 2.2, then
// an iteration 0.9 (backward sweep) + 0.6 (forward) + 0.3 (t, U t) + 0.09 (coarse solve); real
// time = CPU time. (Fusing the diagonal, the copy and E's blocks into one pass over the matrix
// saved nothing measurable: not kept.)
// And the two parts the large meshes are cut into for the threads now hold equal work (a
// vertex's neighbours and itself, the blocks a sweep reads), where they held equal vertex
// counts: liver_x16's second part had 25% more blocks than its first, so the first's thread
// waited at every sweep (the separator, swept by one thread, 8% of the vertices either way).
// Both cuttings in one process, 8-step batches alternated, medians of 50 (three runs): two
// threads 0.967-0.971x the time at 6.70 -> 6.74 iterations; one thread 0.98-0.99x; liver_x4
// (4091 vertices) 0.98-1.00x. cholmod_match liver_x4 0.00092% -> 0.00055%, liver_x16 0.00204% ->
// 0.00246% (the sweeps' order changed with the numbering).
// Then E's factorisation, the one serial piece of a solve's start, runs on one thread while the
// others load the diagonal blocks and the single-precision copy (it joins them when done): two
// threads on liver_x16, the two builds alternated six times, 60 steps each, median step 29.5 ->
// 27.4 ms (solve 21.3 -> 19.8) on a busy VM; ten more alternations in quieter minutes, 22.6 ->
// 21.5 ms, the pairs' ratios 0.83-1.28 (median 0.95), the fastest runs 19.3 -> 19.1: a gain of
// a few percent, at the edge of what this VM resolves. Every result the same to the bit.
//
// 2026-12-08: the assembly's gathers take a vertex's (an edge's) incidences alternately into two
// sets of sums and add the sets at the end: each set's chain of dependent multiply-adds is half
// as long (a vertex has about sixteen incidences, an edge about five; the chain's latency, not
// the loads, bounded the loops). Liver, one thread, the two builds alternated four times, the
// fastest of 9 repetitions each: assembly_ms 0.197-0.266 -> 0.165-0.186; cholmod_match
// (0.0132%), the iterations (6.51) and the residual unchanged to the digits printed. The same
// split of the sweeps' neighbour sums again gained nothing (solve 0.63 -> 0.70 ms in quiet
// pairs). Nor did shortening the sweep's own chain from one row to the next: each row's nearest
// neighbour (the newest value) applied apart as D_c^-1 A_cn y_n, with D_c^-1 A_cn made at the
// solve's start, so that the row's other sums and its D_c^-1 product need not wait for it. The
// same iterates to the digits printed, and the solve slower (fastest of 7, alternated five
// times: 0.57-0.70 -> 0.65-0.72 ms): the sweeps are bound by their work, not that chain.
// Two threads on liver_x16 (1.69-1.77x in the day's goals runs): of every place the reverse
// Cuthill-McKee numbering could be cut in two, the one taken already minimises a sweep's time on
// two threads (the larger part's work plus the separator's, swept by one thread), at 8.8% of the
// work in the separator (liver_x4 8.5%). A smaller separator needs a vertex separator that is
// not one level of the breadth-first search (METIS's, which Debian's CHOLMOD exposes as
// cholmod_metis_bisector): not tried.
//
// Before the stopping rule (2026-11-22, |r| <= 1e-2 |b|): cg 1.46 / 9.71 / 64.6 ms at 15.3 /
// 29.9 / 50.8 iterations, match 0.099% / 0.075% / 0.073% under gravity, but 7-11x Hertz's force
// under contact; the rule costs 23% on the liver and buys the contact force (within 0.06% of
// CHOLMOD's on the Hertz press).
//
// Older (2026-11-22, the old rule), cg on liver.msh, one thread: tolerance 3e-2 / 1e-3 / 1e-4:
// 1.29 / 1.90 / 2.37 ms (11.5 / 24.9 / 35.7 it; match 0.32% / 0.027% / 0.0014%). Rotations: 1 /
// 2 quaternion iterations 1.44 / 1.41 ms (exact_match 1.9% / 0.41%, default 3: 0.15%); SVD 4.24
// ms (rotations 2.89 ms). Linear FEM 1.06 ms (10.2 it).
#include "bench/bench_liver.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "models/corotational_fem/corotational_fem.h"
#include "models/corotational_fem/corotational_fem_model.h"
#include "scenes/shipped_data.h"

#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
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
  // The SSOR solve's coarse level: aggregates of other sizes than the default's, and the whole
  // body as one aggregate (the default below CorotationalFemModel::kCoarseFromVertices).
  for (const int vertices : {32, 128}) {
    Params params;
    params.coarse_vertices = vertices;
    result.push_back({"cg+coarse_" + std::to_string(vertices), params});
  }
  Params whole_body;
  whole_body.coarse_vertices = std::numeric_limits<int>::max();
  result.push_back({"cg+coarse_whole_body", whole_body});
  // The sweeps' matrix in either precision at every size (the default picks by size).
  for (const auto& [label, precision] : {std::pair{"double", Params::SweepPrecision::kDouble},
                                         std::pair{"single", Params::SweepPrecision::kSingle}}) {
    Params params;
    params.sweep_precision = precision;
    result.push_back({std::string("cg+") + label + "_sweeps", params});
  }
  Params jacobi;
  jacobi.preconditioner = Params::Preconditioner::kJacobi;
  result.push_back({"cg+jacobi", jacobi});
  Params last_only;
  last_only.projected_warm_start = false;
  result.push_back({"cg+last_warm_start", last_only});
  Params jacobi_last = jacobi;
  jacobi_last.projected_warm_start = false;
  result.push_back({"cg+jacobi+last_warm_start", jacobi_last});
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

/// Positions after kMatchSteps steps from rest, cached per mesh and parameter set.
const Eigen::Matrix3Xd& positions_after_match_steps(const std::string& mesh_name,
                                                    const Params& params) {
  static std::map<std::string, Eigen::Matrix3Xd> cache;
  const std::string key = mesh_name + corotational_fem::param_table().to_json(params).dump();
  auto found = cache.find(key);
  if (found == cache.end()) {
    const TetMesh& mesh = bench::shipped_liver(mesh_name);
    CorotationalFemModel model(mesh, kLiverMaterial, params);
    const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
    StepInput input;
    input.gravity = {0.0, 0.0, -9.81};
    input.constraints = pins;
    for (int step = 0; step < bench::unless_smoke(kMatchSteps, 2); ++step) {
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
  const Eigen::Matrix3Xd& rest = bench::shipped_liver(mesh_name).rest_positions();
  return std::sqrt((x - x_reference).colwise().squaredNorm().mean()
                   / (x_reference - rest).colwise().squaredNorm().mean());
}

void fem_step(benchmark::State& state,
              const Variant& variant,
              const std::string& mesh_name,
              int threads) {
  omp_set_num_threads(threads);
  const TetMesh& mesh = bench::shipped_liver(mesh_name);
  CorotationalFemModel model(mesh, kLiverMaterial, variant.params);
  const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
  StepInput input;
  input.gravity = {0.0, 0.0, -9.81};
  input.constraints = pins;
  PhaseTimes phases;
  if (!bench::time_steps(
          state, kWarmUpSteps, kStepsPerBatch, [&] { return model.step(kDt, input); },
          [&] { return model.step_timed(kDt, input, &phases); })) {
    return;
  }
  const auto steps = static_cast<double>(state.iterations());
  state.counters["elements_ms"] = 1e3 * phases.elements / steps;
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
            ->Iterations(bench::timed_steps(/*slow=*/false, kStepsPerBatch))
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
