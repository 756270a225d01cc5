// SPDX-License-Identifier: MIT
// Shape matching (models/shape_matching/) against the thesis's experiments:
//
// - BM_ShapeMatchingParticles/<linear|quadratic>/clusters:<K>/particles:<N>: the thesis's
//   Figure 3.10, time per matching step against the number of particles taking part, for
//   random rest and current positions in a unit cube (seeded). One matching step = every
//   cluster's centre of mass, Apq, rotation, map and goals, then every particle's averaged goal.
//   With K > 1 the region radius is chosen so that each particle is in about 2 clusters (2N / K
//   particles per cluster): memberships ~ 2N, so the cost is linear in N, and K adds K polar
//   decompositions and K small 3x9 * 9x9 products. K = 1 is one global cluster (N memberships).
// - BM_HundredObjects: the thesis's "100 objects of 100 particles, 8 clusters each, quadratic:
//   50 FPS": 100 shape-matching bodies on a 5 x 5 x 4 vertex grid, each in 8 clusters of about
//   25 particles (each particle in ~2), one full step (forces, matching, integration) each.
// - BM_ShapeMatchingLiver/<mode>/threads:<T>: one full step on scenes/data/liver.msh (1215
//   vertices) in the scene setting of step_bench (gravity, vertices in the lowest 10% of x
//   pinned, dt 1/60) with the thesis's configuration (quadratic, 50 clusters of ~96 particles,
//   alpha 0.72, beta 0.63) and variants; thesis_one_pass is that configuration stepped as the
//   thesis stepped it (one pass, no volume correction), the others take the defaults' passes.
// - BM_ShapeMatchingHolds/<free|pinned|contact>: one step of that liver holding nothing, the
//   pins (kinematic: they anchor their clusters), or the pins and a contact patch whose fully
//   held vertices change every step (its clusters refitted every step): what held particles
//   cost (holds_benchmark()).
//
// Single-core figures run with OMP threads set to 1 inside the benchmark. The machine is shared
// and noisy: run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true and
// quote medians.
//
// Measured (2-core shared Xeon VM, Debian 12, g++ 12 -O3, no -march; load average 2-4 from
// other jobs, so real-time medians were inflated by up to 2x; the CPU-time medians below are
// the cost on a core the process has to itself):
//
//   Figure 3.10, us per matching step (CPU-time medians):
//     particles   linear K=1   K=8    K=32   quadratic K=1   K=8    K=32
//     100            1.1       2.2     4.8         1.6        3.4     6.8
//     300            2.2       4.2     6.5         3.4        6.7    10.4
//     1000           5.9      11.0    12.4         9.4       18.4    22.2
//     3000          16.7      30.2    31.4        26.7       53.0    56.5
//     10000         54.9     119     133          89.8      203     220
//   Linear in the particles; K > 1 doubles the memberships (each particle in ~2 clusters) and
//   adds K rotations; quadratic costs ~1.6x linear. (At 10000 particles with K > 1 the working
//   set, ~2 MB, leaves L2: ~15% more per particle.)
//   BM_HundredObjects: 0.50 ms per frame of 100 bodies (~2000 frames/s; the thesis: 50 FPS).
//   BM_ShapeMatchingLiver, 1 thread (CPU / real-time medians, steps/s): thesis 64 us (15,600 /
//   10,400 under load), thesis+svd 88 us (11,400), linear 44 us (22,600), one_cluster 22 us,
//   linear_one_cluster 17.5 us. 2 threads: no gain on this loaded machine (72 us at best,
//   0.2-5 ms when the other core was busy: a thread descheduled at a barrier); on a quiet
//   machine an earlier build gave 83 -> 63 us.
//   BM_ShapeMatchingHolds (thread CPU-time medians): free 65.7 us, pinned 72.0 us (1.10x),
//   contact 90.7 us (1.38x; 12.7 contact holds and 5.6 clusters refitted a step).
//   The figures above are one pass a step. With the default four passes (2026-11-25, medians of
//   3, load 1-2): BM_ShapeMatchingLiver thesis 288 us (1 thread; 262 us on 2), thesis+svd 408,
//   linear 189, one_cluster 98.6, linear_one_cluster 78.0; BM_ShapeMatchingHolds free 258 us,
//   pinned 283 us (1.10x), contact 313 us (1.21x: the held clusters' refits are once a step).
//   2026-11-28, x86-64-v3 build, a slow hour (medians of 3): thesis 397 us, thesis_one_pass
//   117 us (8,500 steps/s); bullet_softbody's step in step_bench a minute later 1.05 ms, 9.0x
//   the one pass.
//   2026-12-02, same build flags (medians of 3): before, thesis 285 us, thesis_one_pass 87.2 us
//   (11,500 steps/s). After the moments in four-lane sums (the centre of mass in their first
//   pass), the three goal rows in one pass, the per-particle flight and pulls vectorised over
//   blocks of 256 (constrained particles apart) and no OpenMP region on one thread:
//   thesis_one_pass 49-53 us in six runs (18,900-20,400 steps/s), thesis 203 us, linear 145,
//   one_cluster 61.0, linear_one_cluster 52.3; BM_ShapeMatchingHolds free 182 us, pinned 201 us
//   (1.10x), contact 225 us (1.24x). Same positions and goals to round-off: the sums' order
//   changed, the tests' tolerances hold. In bullet_bench, same process: bullet_softbody's step
//   14.1-14.3x shape_matching:thesis_one_pass's in two runs of three, 12.2x in the third (its
//   first after a build: 73 us there).
//   2026-12-03, bullet_bench, builds alternated, medians of 5: a held cluster's pull sums (its
//   net force and first moment, which the held particles supply) made from rest sums times its
//   fit and one weighted moments pass over the offsets, instead of a gather of every member's
//   position after its goals: shape_matching:thesis_one_pass 19.7k -> 20.5k steps/s,
//   bullet_softbody against it 13.7x -> 14.7x in the same process. Each membership's goal then
//   kept as x, y, z side by side (one four-lane load a membership in the per-particle gather):
//   19.7-19.8k -> 20.7k steps/s against the code before both. Positions to round-off (the sums'
//   order changed).
//   2026-12-08, bullet_bench, builds alternated (CPU-time medians of 7): the members' offsets
//   gathered four at a time into vectors (one subtract, multiply and store a coordinate where
//   the scalar loop took three of each a member), the goals made eight members at a time (each
//   of the fit's 27 coefficients, which do not fit in the registers beside the sums, loaded once
//   for two vectors of members), and the moments' twelve sums as named vectors (an array of them
//   was cleared by a `rep stos` at each of the three calls a cluster): thesis_one_pass 50-53 ->
//   45-47 us (bullet_softbody 0.68-0.71 ms in the same minutes, 14.0x -> 15.0-15.2x). Positions
//   to round-off (1e-15 relative on the liver's recovery residual). Tried and not kept: each
//   particle's goal summed by adding each membership's goal into it as its cluster is matched
//   (no per-particle gather: 1-2% faster, not worth a second way to sum the goals), the
//   per-particle gathers padded to four memberships (no change), the last n mod 8 goals in
//   zero-padded lanes (slower), the constrained particles' loops over the constraint lists
//   instead of every particle (no change), AVX2's gather instructions for the members' offsets
//   (slower: 46-47 -> 49-50 us). BM_ShapeMatchingHolds (four passes, medians of 3)
//   after: free 158 us, pinned 179 us (1.13x), contact 202 us (1.28x).
#include "bench/bench_liver.h"
#include "bench/thread_cpu_clock.h"
#include "geometry/mesh_data.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"
#include "models/shape_matching/cluster_matching.h"
#include "models/shape_matching/clusters.h"
#include "models/shape_matching/shape_matching.h"
#include "models/shape_matching/shape_matching_model.h"
#include "scenes/shipped_data.h"

#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace softbench {
namespace {

using Params = ShapeMatchingParams;

/// The scenes' step.
constexpr double kDt = 1.0 / 60.0;
constexpr int kWarmUpSteps = 10;
/// The liver material of the scenes (only the density matters here).
const Material kLiverMaterial{3000.0, 0.3, 1060.0};

// ---------------------------------------------------------------------------------------------
// Figure 3.10

/// N points uniformly in the unit cube, from a fixed seed.
Eigen::Matrix3Xd random_points(int count, unsigned seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix3Xd points(3, count);
  for (int i = 0; i < count; ++i) {
    points.col(i) = Eigen::Vector3d(unit(generator), unit(generator), unit(generator));
  }
  return points;
}

/// Each particle in about `overlap` clusters: clusters of overlap * N / K particles.
shape_matching::ClusterSpec overlapping(int clusters, int particles, int overlap) {
  return {clusters, 0.0, std::max(4, overlap * particles / clusters)};
}

void particles_benchmark(benchmark::State& state, Params::Type type, int clusters) {
  omp_set_num_threads(1);
  const int particles = static_cast<int>(state.range(0));
  const Eigen::Matrix3Xd rest = random_points(particles, 2005);
  const Eigen::Matrix3Xd current = random_points(particles, 2016);
  const Eigen::VectorXd masses = Eigen::VectorXd::Ones(particles);
  const shape_matching::Clusters built =
      shape_matching::build_clusters(rest, overlapping(clusters, particles, 2));
  Params params;
  params.type = type;
  shape_matching::ClusterMatcher matcher(rest, masses, built, params);
  Eigen::Matrix3Xd goals(3, particles);
  for (int step = 0; step < kWarmUpSteps; ++step) {
    matcher.match(current, goals);
  }
  std::chrono::duration<double, std::nano> elapsed{0.0};
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    matcher.match(current, goals);
    elapsed += std::chrono::steady_clock::now() - start;
    benchmark::DoNotOptimize(goals.data());
    benchmark::ClobberMemory();
  }
  const auto steps = static_cast<double>(state.iterations());
  state.counters["particles"] = particles;
  state.counters["clusters"] = matcher.num_clusters();
  state.counters["memberships"] = matcher.num_memberships();
  state.counters["ns_per_particle"] = elapsed.count() / (steps * particles);
  state.counters["steps_per_s"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
}

// ---------------------------------------------------------------------------------------------
// Meshes

/// A box of nx x ny x nz vertices (spacing h), each cell split into 6 tets (Kuhn).
MeshData grid_box(int nx, int ny, int nz, double h) {
  MeshData data;
  data.vertices.resize(3, nx * ny * nz);
  const auto vertex = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        data.vertices.col(vertex(i, j, k)) = h * Eigen::Vector3d(i, j, k);
      }
    }
  }
  // The 6 tets of the Kuhn split share the diagonal from corner 0 to corner 7.
  constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7},
                               {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  std::vector<Eigen::Vector4i> tets;
  for (int k = 0; k + 1 < nz; ++k) {
    for (int j = 0; j + 1 < ny; ++j) {
      for (int i = 0; i + 1 < nx; ++i) {
        int corner[8];
        for (int c = 0; c < 8; ++c) {
          corner[c] = vertex(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        }
        for (const auto& tet : kTets) {
          tets.emplace_back(corner[tet[0]], corner[tet[1]], corner[tet[2]], corner[tet[3]]);
        }
      }
    }
  }
  data.tetrahedra.resize(4, static_cast<Eigen::Index>(tets.size()));
  for (std::size_t t = 0; t < tets.size(); ++t) {
    data.tetrahedra.col(static_cast<Eigen::Index>(t)) = tets[t];
  }
  return data;
}

// ---------------------------------------------------------------------------------------------
// The hundred objects

void hundred_objects_benchmark(benchmark::State& state) {
  omp_set_num_threads(1);
  constexpr int kObjects = 100;
  static const TetMesh object = make_tet_mesh(grid_box(5, 5, 4, 0.01));  // 100 vertices
  Params params;
  params.type = Params::Type::kQuadratic;
  params.clusters = 8;
  params.particles_per_cluster = 2 * object.num_vertices() / params.clusters;
  std::vector<std::unique_ptr<SoftBody>> bodies;
  for (int b = 0; b < kObjects; ++b) {
    bodies.push_back(make_shape_matching(object, kLiverMaterial, params));
  }
  const StepInput input;  // gravity, no constraints
  for (int step = 0; step < kWarmUpSteps; ++step) {
    for (const auto& body : bodies) {
      body->step(kDt, input);
    }
  }
  bool finite = true;
  for (auto _ : state) {
    for (const auto& body : bodies) {
      finite = body->step(kDt, input).finite && finite;
    }
  }
  if (!finite) {
    state.SkipWithError("a body blew up");
    return;
  }
  state.counters["objects"] = kObjects;
  state.counters["particles_per_object"] = object.num_vertices();
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// ---------------------------------------------------------------------------------------------
// The liver

struct LiverMode {
  std::string label;
  Params params;
};

std::vector<LiverMode> liver_modes() {
  Params thesis;  // the defaults are the thesis's: quadratic, 50 clusters, 96, 0.72, 0.63
  thesis.type = Params::Type::kQuadratic;
  thesis.clusters = 50;
  thesis.particles_per_cluster = 96;
  thesis.alpha = 0.72;
  thesis.beta = 0.63;
  std::vector<LiverMode> modes{{"thesis", thesis}};
  // The step as the thesis ran it, Mueller 2005's: one match and pull, no volume correction
  // (the defaults' four passes and volume correction are for a hanging body).
  Params one_pass = thesis;
  one_pass.iterations = 1;
  one_pass.preserve_volume = false;
  modes.push_back({"thesis_one_pass", one_pass});
  Params svd = thesis;
  svd.rotation = Params::Rotation::kSvd;
  modes.push_back({"thesis+svd", svd});
  Params linear = thesis;
  linear.type = Params::Type::kLinear;
  modes.push_back({"linear", linear});
  Params one_cluster = thesis;
  one_cluster.clusters = 1;
  modes.push_back({"one_cluster", one_cluster});
  Params linear_one_cluster = linear;
  linear_one_cluster.clusters = 1;
  modes.push_back({"linear_one_cluster", linear_one_cluster});
  return modes;
}

void liver_benchmark(benchmark::State& state, const Params& params, int threads) {
  omp_set_num_threads(threads);
  const TetMesh& mesh = bench::shipped_liver("liver.msh");
  const std::unique_ptr<SoftBody> body = make_shape_matching(mesh, kLiverMaterial, params);
  const std::vector<PositionConstraint> pins = bench::pin_lowest_tenth_in_x(mesh);
  StepInput input;
  input.constraints = pins;
  for (int step = 0; step < kWarmUpSteps; ++step) {
    body->step(kDt, input);
  }
  bench::StepTotals totals;
  for (auto _ : state) {
    totals.add(body->step(kDt, input));
  }
  omp_set_num_threads(1);
  if (!totals.report(state)) {
    return;
  }
  state.counters["vertices"] = mesh.num_vertices();
  state.counters["threads"] = threads;
  const auto& model = dynamic_cast<const shape_matching::ShapeMatchingModel&>(*body);
  state.counters["clusters"] = model.matcher().num_clusters();
  state.counters["mean_cluster_size"] =
      static_cast<double>(model.matcher().num_memberships()) / model.matcher().num_clusters();
  state.counters["cluster_radius_mm"] = 1000.0 * model.clusters().radius;
}

// ---------------------------------------------------------------------------------------------
// Held particles

/// What a step holds in BM_ShapeMatchingHolds.
enum class Holds { kNone, kPinned, kContact };

/// The liver as in BM_ShapeMatchingLiver (thesis configuration, gravity, one thread), holding:
/// nothing (kNone: the free step); the lowest tenth in x pinned (kPinned: a fixed held set,
/// refitted once); or those pins and a contact patch that moves (kContact): the surface
/// vertices within 1.5 cm of a surface vertex that steps, one a step, through the upper
/// surface within 3 cm of where liver_press's probe comes down, are held fully (kinematic, as
/// the instrument holds the corners of the triangles it pushes), and those 1.5 to 2 cm from it
/// slide along z (a frictionless contact), all where they are. The held set changes every
/// step, so the clusters around it are refitted every step (more often than in liver_press
/// and liver_pull, whose contact changes a few vertices a pass): `refits` is the mean number
/// per step, `contact_holds` the mean number of contact constraints. Each step is timed on the
/// thread's CPU clock (the reported time; building the step's constraints is left out), so a
/// loaded machine inflates it less.
void holds_benchmark(benchmark::State& state, Holds holds) {
  omp_set_num_threads(1);
  const TetMesh& mesh = bench::shipped_liver("liver.msh");
  Params params;  // the thesis's
  const std::unique_ptr<SoftBody> body = make_shape_matching(mesh, kLiverMaterial, params);
  const auto& model = dynamic_cast<const shape_matching::ShapeMatchingModel&>(*body);
  const std::vector<PositionConstraint> pins =
      holds == Holds::kNone ? std::vector<PositionConstraint>{}
                            : bench::pin_lowest_tenth_in_x(mesh);
  std::vector<int> surface;
  {
    std::vector<bool> on_surface(static_cast<std::size_t>(mesh.num_vertices()), false);
    const Eigen::Matrix3Xi triangles = boundary_triangles(mesh.tets());
    for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
      for (int c = 0; c < 3; ++c) {
        on_surface[static_cast<std::size_t>(triangles(c, t))] = true;
      }
    }
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (on_surface[static_cast<std::size_t>(v)]) {
        surface.push_back(v);
      }
    }
  }
  // The path of the patch's centre: the upper surface vertices within 3 cm of where
  // liver_press's probe comes down (x = 3.7 cm, y = 0.4 cm; those above the liver's mid
  // height), in order of x, there and back, one a step.
  const double middle = 0.5 * (mesh.rest_positions().row(2).minCoeff()
                               + mesh.rest_positions().row(2).maxCoeff());
  std::vector<int> path;
  for (const int v : surface) {
    const Eigen::Vector3d x = mesh.rest_positions().col(v);
    if (std::hypot(x.x() - 0.037, x.y() - 0.004) < 0.03 && x.z() > middle) {
      path.push_back(v);
    }
  }
  std::sort(path.begin(), path.end(), [&](int a, int b) {
    return mesh.rest_positions()(0, a) < mesh.rest_positions()(0, b);
  });
  for (std::size_t back = path.size(); back-- > 1;) {
    path.push_back(path[back - 1]);
  }
  std::vector<PositionConstraint> constraints;
  constraints.reserve(pins.size() + surface.size());
  int step = 0;
  const auto input_for = [&](int index) {
    constraints.assign(pins.begin(), pins.end());
    if (holds == Holds::kContact) {
      const Eigen::Vector3d centre =
          body->positions().col(path[static_cast<std::size_t>(index) % path.size()]);
      for (const int v : surface) {
        const Eigen::Vector3d x = body->positions().col(v);
        const double distance = (x - centre).norm();
        if (distance < 0.015) {
          constraints.push_back({v, x, kExact});
        } else if (distance < 0.02) {
          constraints.push_back({v, x, kExact, PositionConstraint::along(Eigen::Vector3d::UnitZ())});
        }
      }
    }
    StepInput input;
    input.constraints = constraints;
    return input;
  };
  for (; step < kWarmUpSteps; ++step) {
    body->step(kDt, input_for(step));
  }
  bench::StepTotals totals;
  double refits = 0.0;
  double held_clusters = 0.0;
  double held_particles = 0.0;
  for (auto _ : state) {
    const StepInput input = input_for(step++);
    const double start = bench::thread_cpu_us();
    totals.add(body->step(kDt, input));
    state.SetIterationTime(1e-6 * (bench::thread_cpu_us() - start));
    refits += model.matcher().num_refits();
    held_particles += static_cast<double>(input.constraints.size() - pins.size());
    held_clusters += model.matcher().num_held_clusters();
  }
  if (!totals.report(state)) {
    return;
  }
  const auto steps = static_cast<double>(state.iterations());
  state.counters["refits"] = refits / steps;
  state.counters["held_clusters"] = held_clusters / steps;
  state.counters["contact_holds"] = held_particles / steps;
}

void register_benchmarks() {
  for (const auto& [label, type] : {std::pair{"linear", Params::Type::kLinear},
                                    std::pair{"quadratic", Params::Type::kQuadratic}}) {
    for (const int clusters : {1, 8, 32}) {
      benchmark::RegisterBenchmark(("BM_ShapeMatchingParticles/" + std::string(label)
                                    + "/clusters:" + std::to_string(clusters))
                                       .c_str(),
                                   [type = type, clusters](benchmark::State& state) {
                                     particles_benchmark(state, type, clusters);
                                   })
          ->ArgName("particles")
          ->Arg(100)
          ->Arg(300)
          ->Arg(1000)
          ->Arg(3000)
          ->Arg(10000)
          ->Unit(benchmark::kMicrosecond)
          ->UseRealTime();
    }
  }
  for (const auto& [label, holds] : {std::pair{"free", Holds::kNone},
                                     std::pair{"pinned", Holds::kPinned},
                                     std::pair{"contact", Holds::kContact}}) {
    benchmark::RegisterBenchmark(("BM_ShapeMatchingHolds/" + std::string(label)).c_str(),
                                 [holds = holds](benchmark::State& state) {
                                   holds_benchmark(state, holds);
                                 })
        ->Unit(benchmark::kMicrosecond)
        ->UseManualTime();
  }
  benchmark::RegisterBenchmark("BM_HundredObjects", hundred_objects_benchmark)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  for (const LiverMode& mode : liver_modes()) {
    for (const int threads : {1, 2}) {
      benchmark::RegisterBenchmark(
          ("BM_ShapeMatchingLiver/" + mode.label + "/threads:" + std::to_string(threads)).c_str(),
          [params = mode.params, threads](benchmark::State& state) {
            liver_benchmark(state, params, threads);
          })
          ->Unit(benchmark::kMicrosecond)
          ->UseRealTime();
    }
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
