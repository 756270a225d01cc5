// SPDX-License-Identifier: MIT
// Table 4.2 of the thesis: per-frame collision cost between the deforming liver and the rigid
// instrument at increasing contact (0 to ~1100 intersecting triangle pairs), for the hybrid
// Sphere-AABB tree, the all-sphere and all-AABB trees (same code, other schedules), and FCL 0.7's
// BVHModel<AABBd> as the outside peer.
//
// Meshes: the shipped liver (scenes/data/liver.msh), as (a) every unique face of its tets (the
// thesis collided the full tet-face set, 9313 triangles there), (b) its boundary surface and
// (c) that surface conforming to the probe (see conformed(): the rigid probe alone makes at most
// ~140 pairs with the coarse surface, so (c) covers ~100 to ~1100); the
// instrument scenes/data/instrument_probe.obj (a 3 mm radius probe), laid along x over the liver
// and lowered along -z. The lowering depth for each target pair count is found by a scan plus
// bisection on the hybrid tree's exact count; the benchmark reports the count it actually got.
//
// A frame: switch the liver between two vertex sets that differ by a 0.1 mm breathing motion
// (scaling about the centroid), refit both trees (the instrument, being rigid, is passed already
// in world coordinates), query, and run the exact projection test on every candidate. FCL gets
// the same: pre-transformed vertices and identity transforms (its AABB path otherwise
// re-transforms and refits on every call), bottom-up refit of both models, collide() with all
// contacts and contact points (the analogue of our segments).
// Counters: refit_us and query_us split the frame; pairs is the intersecting-pair count.
// BM_Compare times hybrid, sphere and AABB interleaved (see run_compare) for the goal check.
#include "bench/bench_smoke.h"
#include "bench/thread_cpu_clock.h"
#include "collision/bvh.h"
#include "collision/bvh_collide.h"
#include "collision/bvh_schedule.h"
#include "collision/tri_tri_projection.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_topology.h"
#include "scenes/shipped_data.h"

#include <Eigen/Geometry>
#include <benchmark/benchmark.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace softbench::collision {
namespace {

// Parts are timed on the thread's CPU clock (bench/thread_cpu_clock.h); the clock's own cost is
// in the counters, not the frame time.
using bench::thread_cpu_us;

constexpr std::array<int, 8> kTargetPairs = {0, 32, 97, 279, 534, 733, 925, 1106};
constexpr double kBreathing = 1e-4;   // m: largest vertex displacement between the two sets
constexpr double kScanStep = 2.5e-4;  // m: depth step of the placement scan
constexpr double kScanRange = 0.05;   // m: how far past first contact the scan goes
// m: the "0 pairs" placement is this far above first contact: close enough that the trees
// descend (the thesis's instrument approaching), far enough that breathing does not touch.
constexpr double kClearance = 2.5e-4;
// Conforming scenes (see conformed()): bands scanned, in probe radii, and the radial jitter.
constexpr double kConformFirstBand = 1.0;
constexpr double kConformStep = 0.125;
constexpr double kConformRange = 24.0;
constexpr double kConformJitter = 0.3;

// Every unique face of the tets (orientation irrelevant for collision), sorted.
Eigen::Matrix3Xi unique_tet_faces(const Eigen::Matrix4Xi& tets) {
  std::vector<std::array<int, 3>> faces;
  faces.reserve(static_cast<std::size_t>(4 * tets.cols()));
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face{};
      int k = 0;
      for (int i = 0; i < 4; ++i) {
        if (i != skip) {
          face[static_cast<std::size_t>(k++)] = tets(i, t);
        }
      }
      std::sort(face.begin(), face.end());
      faces.push_back(face);
    }
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  Eigen::Matrix3Xi result(3, static_cast<Eigen::Index>(faces.size()));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    result.col(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  }
  return result;
}

struct Scene {
  std::string name;
  Eigen::Matrix3Xi liver_triangles;
  Eigen::Matrix3Xd liver_rest;
  Eigen::Matrix3Xi tool_triangles;
  Eigen::Matrix3Xd tool_rest;  // laid along x, lowest point at the liver's top, not yet lowered
  double tool_radius = 0.0;    // m: the probe shaft's radius
  // Conforming scenes keep the probe pressed in by its radius and vary how wide a band of liver
  // vertices wraps around it (placement parameter: the band, in probe radii); the others lower
  // the rigid probe onto the undeformed liver (parameter: the depth, m).
  bool conforming = false;
};

// Where both meshes are at one placement: the instrument in world coordinates and the liver's
// two breathing states.
struct Pose {
  Eigen::Matrix3Xd tool;
  std::array<Eigen::Matrix3Xd, 2> liver;
};

Eigen::Matrix3Xd lowered(const Scene& scene, double depth) {
  Eigen::Matrix3Xd world = scene.tool_rest;
  world.row(2).array() -= depth;
  return world;
}

// The liver and the same scaled about its centroid by kBreathing at the farthest vertex.
std::array<Eigen::Matrix3Xd, 2> breathing(const Eigen::Matrix3Xd& liver) {
  const Eigen::Vector3d centroid = liver.rowwise().mean();
  const double reach = (liver.colwise() - centroid).colwise().norm().maxCoeff();
  return {liver, ((liver.colwise() - centroid) * (1.0 + kBreathing / reach)).colwise() + centroid};
}

// Soft tissue conforming to the tool: liver vertices within band * r of the probe's axis (and
// within its length) move radially onto radius r (1 +- kConformJitter), the sign alternating
// with the vertex index, so that the liver's triangles zig-zag across the probe's surface as
// tissue pressed around an instrument does. The rigid probe alone cannot make more than ~140
// pairs with the 1622-triangle surface (its triangles are large: a straight probe crosses few of
// them), conforming tissue can.
Eigen::Matrix3Xd conformed(const Scene& scene, const Eigen::Matrix3Xd& tool, double band) {
  const Eigen::Vector3d lo = tool.rowwise().minCoeff(), hi = tool.rowwise().maxCoeff();
  const Eigen::Vector3d axis = 0.5 * (lo + hi);
  Eigen::Matrix3Xd liver = scene.liver_rest;
  for (Eigen::Index v = 0; v < liver.cols(); ++v) {
    if (liver(0, v) < lo.x() || liver(0, v) > hi.x()) {
      continue;
    }
    const Eigen::Vector2d offset(liver(1, v) - axis.y(), liver(2, v) - axis.z());
    const double distance = offset.norm();
    if (distance > 0.0 && distance < band * scene.tool_radius) {
      const double radius =
          scene.tool_radius * (1.0 + (v % 2 == 0 ? kConformJitter : -kConformJitter));
      liver.block<2, 1>(1, v) = Eigen::Vector2d(axis.y(), axis.z()) + offset * (radius / distance);
    }
  }
  return liver;
}

Pose make_pose(const Scene& scene, double parameter) {
  if (!scene.conforming) {
    return {lowered(scene, parameter), breathing(scene.liver_rest)};
  }
  Eigen::Matrix3Xd tool = lowered(scene, scene.tool_radius);
  std::array<Eigen::Matrix3Xd, 2> liver = breathing(conformed(scene, tool, parameter));
  return {std::move(tool), std::move(liver)};
}

struct Trees {
  Bvh liver;
  Bvh tool;
};

// Built at rest (as a simulation builds them once), refitted per frame.
Trees build_trees(const Scene& scene, const BvhSchedule& liver, const BvhSchedule& tool) {
  return {Bvh(scene.liver_rest, scene.liver_triangles, liver),
          Bvh(scene.tool_rest, scene.tool_triangles, tool)};
}

int count_pairs(Trees& trees, const Scene& scene, double parameter) {
  const Pose pose = make_pose(scene, parameter);
  trees.liver.refit(pose.liver[0]);
  trees.tool.refit(pose.tool);
  CollideBuffers buffers;
  std::vector<TrianglePair> pairs;
  collide(trees.liver, pose.liver[0], trees.tool, pose.tool, buffers, pairs);
  return static_cast<int>(pairs.size());
}

struct Placement {
  int target = 0;
  double parameter = 0.0;  // depth (m) or band (probe radii), see Scene
  int pairs = 0;
  Pose pose;
};

// Placement parameters for the target counts: a scan from first contact (conforming scenes: from
// the narrowest band), then bisection inside the first scan step whose counts reach the target.
// The first target above the scan's maximum gets the maximum's parameter (reported); later ones
// are dropped. Conforming scenes skip the targets below their first count (the rigid placements
// of the same surface cover those).
std::vector<Placement> find_placements(const Scene& scene) {
  Trees trees = build_trees(scene, BvhSchedule::liver(), BvhSchedule::instrument());
  double contact = kConformFirstBand, step_size = kConformStep, range = kConformRange;
  if (!scene.conforming) {
    // First contact: the first scan step with a pair, then bisection inside it (the count is
    // not monotone in depth, on the surface it drops to 0 once the probe is submerged).
    double hi = 0.0;
    while (count_pairs(trees, scene, hi) == 0) {
      hi += kScanStep;
    }
    double lo = hi - kScanStep;
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      (count_pairs(trees, scene, mid) > 0 ? hi : lo) = mid;
    }
    contact = hi;
    step_size = kScanStep;
    range = kScanRange;
  }
  std::vector<double> parameters;
  std::vector<int> counts;
  for (double d = contact; d <= contact + range; d += step_size) {
    parameters.push_back(d);
    counts.push_back(count_pairs(trees, scene, d));
  }
  std::vector<Placement> placements;
  for (const int target : kTargetPairs) {
    if (scene.conforming && target < counts.front()) {
      continue;
    }
    if (target == 0) {
      const double depth = contact - kClearance;
      placements.push_back({target, depth, count_pairs(trees, scene, depth), {}});
      continue;
    }
    std::size_t step = 1;
    while (step < counts.size() && counts[step] < target) {
      ++step;
    }
    if (step == counts.size()) {
      // Unreachable: the most the scan found, once; the later targets are dropped.
      const auto best =
          static_cast<std::size_t>(std::max_element(counts.begin(), counts.end()) - counts.begin());
      placements.push_back({target, parameters[best], counts[best], {}});
      std::fprintf(stderr, "%s: at most %d pairs in the scan; targets from %d on not reached\n",
                   scene.name.c_str(), placements.back().pairs, target);
      break;
    }
    double a = parameters[step - 1], b = parameters[step];
    Placement best{target, b, counts[step], {}};
    for (int i = 0; i < 30; ++i) {
      const double mid = 0.5 * (a + b);
      const int count = count_pairs(trees, scene, mid);
      if (std::abs(count - target) < std::abs(best.pairs - target)) {
        best = {target, mid, count, {}};
      }
      (count < target ? a : b) = mid;
    }
    placements.push_back(best);
  }
  for (Placement& placement : placements) {
    placement.pose = make_pose(scene, placement.parameter);
  }
  return placements;
}

Scene make_scene(const std::string& name,
                 const MeshData& liver,
                 const Eigen::Matrix3Xi& triangles,
                 const MeshData& tool) {
  Scene scene;
  scene.name = name;
  scene.liver_triangles = triangles;
  const Eigen::Matrix3Xd& rest = liver.vertices;
  scene.liver_rest = rest;
  // The probe's axis is z from 0 to its length: turn it onto x, centre it over the liver's
  // bounding box, and put its lowest point at the liver's highest.
  const Eigen::Matrix3d z_to_x = Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitY()).matrix();
  Eigen::Matrix3Xd turned = z_to_x * tool.vertices;
  const Eigen::Vector3d tool_center =
      0.5 * (turned.rowwise().minCoeff() + turned.rowwise().maxCoeff());
  const Eigen::Vector3d liver_center =
      0.5 * (rest.rowwise().minCoeff() + rest.rowwise().maxCoeff());
  Eigen::Vector3d shift = liver_center - tool_center;
  shift.z() = rest.row(2).maxCoeff() - turned.row(2).minCoeff();
  scene.tool_rest = turned.colwise() + shift;
  scene.tool_triangles = tool.triangles;
  scene.tool_radius = 0.5 * (turned.row(1).maxCoeff() - turned.row(1).minCoeff());
  return scene;
}

std::vector<fcl::Vector3d> to_fcl(const Eigen::Matrix3Xd& positions) {
  std::vector<fcl::Vector3d> points(static_cast<std::size_t>(positions.cols()));
  for (Eigen::Index i = 0; i < positions.cols(); ++i) {
    points[static_cast<std::size_t>(i)] = positions.col(i);
  }
  return points;
}

std::shared_ptr<fcl::BVHModel<fcl::AABBd>> fcl_model(const Eigen::Matrix3Xd& positions,
                                                     const Eigen::Matrix3Xi& triangles) {
  auto model = std::make_shared<fcl::BVHModel<fcl::AABBd>>();
  std::vector<fcl::Triangle> fcl_triangles;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    fcl_triangles.emplace_back(static_cast<std::size_t>(triangles(0, t)),
                               static_cast<std::size_t>(triangles(1, t)),
                               static_cast<std::size_t>(triangles(2, t)));
  }
  model->beginModel();
  model->addSubModel(to_fcl(positions), fcl_triangles);
  model->endModel();
  return model;
}

// Per-frame averages of the parts (CPU microseconds) and of the counts.
struct FrameTotals {
  double refit_us = 0, broad_us = 0, narrow_us = 0, pairs = 0, tri_tests = 0;
};

void set_frame_counters(benchmark::State& state, const FrameTotals& totals) {
  const auto frames = static_cast<double>(state.iterations());
  state.counters["refit_us"] = totals.refit_us / frames;
  state.counters["query_us"] = (totals.broad_us + totals.narrow_us) / frames;
  state.counters["broad_us"] = totals.broad_us / frames;
  state.counters["narrow_us"] = totals.narrow_us / frames;
  state.counters["pairs"] = totals.pairs / frames;
  state.counters["tri_tests"] = totals.tri_tests / frames;
}

// One frame: refit both trees to this frame's vertices, the broad phase, the exact tests on its
// candidates. `marks` (optional) receives the thread CPU time after each of the three.
void run_frame(Trees& trees,
               const Eigen::Matrix3Xd& liver,
               const Eigen::Matrix3Xd& tool,
               CollideBuffers& buffers,
               std::vector<TrianglePair>& pairs,
               QueryStats& stats,
               bool batched,
               std::array<double, 3>* marks = nullptr) {
  auto mark = [marks](std::size_t phase) {
    if (marks != nullptr) {
      (*marks)[phase] = thread_cpu_us();
    }
  };
  trees.liver.refit(liver);
  trees.tool.refit(tool);
  mark(0);
  stats = {};
  collect_candidates(trees.liver, liver, trees.tool, tool, buffers, stats);
  mark(1);
  if (batched) {
    narrow_phase(trees.liver, liver, trees.tool, tool, buffers, pairs, TriTriMethod::kBatched);
  } else {
    narrow_phase(trees.liver, liver, trees.tool, tool, buffers.candidates, pairs,
                 tri_tri_projection);
  }
  mark(2);
  benchmark::DoNotOptimize(pairs.data());
}

void run_ours(benchmark::State& state,
              const Scene& scene,
              const Placement& placement,
              const BvhSchedule& liver_schedule,
              const BvhSchedule& tool_schedule,
              bool batched) {
  Trees trees = build_trees(scene, liver_schedule, tool_schedule);
  const Eigen::Matrix3Xd& tool = placement.pose.tool;
  CollideBuffers buffers;
  std::vector<TrianglePair> pairs;
  QueryStats stats;
  FrameTotals totals;
  std::size_t frame = 0;
  for (auto _ : state) {
    const Eigen::Matrix3Xd& liver = placement.pose.liver[frame++ % 2];
    std::array<double, 3> marks{};
    const double start = thread_cpu_us();
    run_frame(trees, liver, tool, buffers, pairs, stats, batched, &marks);
    totals.refit_us += marks[0] - start;
    totals.broad_us += marks[1] - marks[0];
    totals.narrow_us += marks[2] - marks[1];
    totals.pairs += static_cast<double>(pairs.size());
    totals.tri_tests += static_cast<double>(buffers.candidates.size());
  }
  set_frame_counters(state, totals);
  state.counters["node_visits"] = static_cast<double>(stats.node_visits);
  state.counters["leaf_visits"] = static_cast<double>(stats.leaf_visits);
}

void run_fcl(benchmark::State& state, const Scene& scene, const Placement& placement) {
  const Eigen::Matrix3Xd& tool = placement.pose.tool;
  auto liver_model = fcl_model(placement.pose.liver[0], scene.liver_triangles);
  auto tool_model = fcl_model(tool, scene.tool_triangles);
  const std::array<std::vector<fcl::Vector3d>, 2> liver_states = {to_fcl(placement.pose.liver[0]),
                                                                  to_fcl(placement.pose.liver[1])};
  const std::vector<fcl::Vector3d> tool_state = to_fcl(tool);
  fcl::CollisionObjectd liver_object(liver_model, fcl::Transform3d::Identity());
  fcl::CollisionObjectd tool_object(tool_model, fcl::Transform3d::Identity());
  fcl::CollisionRequestd request(1000000, /*enable_contact=*/true);
  fcl::CollisionResultd result;
  FrameTotals totals;
  std::size_t frame = 0;
  for (auto _ : state) {
    const double start = thread_cpu_us();
    liver_model->beginUpdateModel();
    liver_model->updateSubModel(liver_states[frame++ % 2]);
    liver_model->endUpdateModel(/*refit=*/true, /*bottomup=*/true);
    tool_model->beginUpdateModel();
    tool_model->updateSubModel(tool_state);
    tool_model->endUpdateModel(true, true);
    liver_object.computeAABB();
    tool_object.computeAABB();
    const double refitted = thread_cpu_us();
    result.clear();
    fcl::collide(&liver_object, &tool_object, request, result);
    const double queried = thread_cpu_us();
    totals.refit_us += refitted - start;
    totals.broad_us += queried - refitted;  // FCL's query is not split: all of it here
    totals.pairs += static_cast<double>(result.numContacts());
  }
  set_frame_counters(state, totals);
}

// The trees of table 4.2 (hybrid_top: sphere+AABB from the root, no sphere-only level, an
// investigated variant; hybrid_batched: the thesis's hybrid with the structure-of-arrays narrow
// phase).
struct TreeKind {
  const char* name;
  BvhSchedule liver, tool;
  bool batched;
};

const std::vector<TreeKind>& tree_kinds() {
  static const std::vector<TreeKind> kinds = {
      {"hybrid", BvhSchedule::liver(), BvhSchedule::instrument(), false},
      {"sphere", BvhSchedule::all_sphere(11), BvhSchedule::all_sphere(9), false},
      {"aabb", BvhSchedule::all_aabb(11), BvhSchedule::all_aabb(9), false},
      {"hybrid_top", BvhSchedule::layered(0, 6, 5, 10), BvhSchedule::layered(0, 4, 5, 10), false},
      {"hybrid_batched", BvhSchedule::liver(), BvhSchedule::instrument(), true}};
  return kinds;
}

// The goal "hybrid at least as fast as the better of sphere and AABB" compares differences of a
// few percent on a machine shared with other jobs, so the three trees are timed interleaved:
// one iteration runs kCompareBatch frames of each tree, in an order that cycles through all six
// permutations (each tree runs first, second and third, after each of the others, equally often:
// the tree that ran before leaves the caches in its own state), and each tree's CPU time is summed
// over its batches. Load changes then hit all three alike, and the repetitions' medians of the
// per-tree times and of their ratio are compared.
constexpr int kCompareBatch = 16;

void run_compare(benchmark::State& state, const Scene& scene, const Placement& placement) {
  const std::array<const TreeKind*, 3> kinds = {&tree_kinds()[0], &tree_kinds()[1],
                                                &tree_kinds()[2]};
  std::vector<Trees> trees;
  for (const TreeKind* kind : kinds) {
    trees.push_back(build_trees(scene, kind->liver, kind->tool));
  }
  const Eigen::Matrix3Xd& tool = placement.pose.tool;
  CollideBuffers buffers;
  std::vector<TrianglePair> pairs;
  std::array<double, 3> total_us{};
  std::array<std::size_t, 3> found{};
  constexpr std::array<std::array<std::size_t, 3>, 6> kOrders = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  std::size_t iteration = 0;
  for (auto _ : state) {
    for (const std::size_t t : kOrders[iteration % kOrders.size()]) {
      const double start = thread_cpu_us();
      for (int f = 0; f < kCompareBatch; ++f) {
        const Eigen::Matrix3Xd& liver = placement.pose.liver[static_cast<std::size_t>(f % 2)];
        QueryStats stats;
        run_frame(trees[t], liver, tool, buffers, pairs, stats, /*batched=*/false);
      }
      total_us[t] += thread_cpu_us() - start;
      found[t] = pairs.size();
    }
    ++iteration;
  }
  if (found[0] != found[1] || found[0] != found[2]) {
    state.SkipWithError("the trees found different pair counts");
    return;
  }
  const double frames = static_cast<double>(state.iterations()) * kCompareBatch;
  for (std::size_t t = 0; t < kinds.size(); ++t) {
    state.counters[std::string(kinds[t]->name) + "_us"] = total_us[t] / frames;
  }
  state.counters["hybrid_over_best"] = total_us[0] / std::min(total_us[1], total_us[2]);
  state.counters["pairs"] = static_cast<double>(found[0]);
}

void register_benchmarks() {
  const MeshData liver = read_mesh(scenes::shipped_data_file("liver.msh"));
  const MeshData tool = read_mesh(scenes::shipped_data_file("instrument_probe.obj"));
  // Scenes and placements live for the whole run: the lambdas below refer to them.
  static std::vector<Scene> scenes;
  static std::vector<std::vector<Placement>> placements;
  scenes.push_back(make_scene("tet_faces", liver, unique_tet_faces(liver.tetrahedra), tool));
  scenes.push_back(make_scene("surface", liver, boundary_triangles(liver.tetrahedra), tool));
  scenes.push_back(scenes.back());
  scenes.back().name = "surface_conforming";
  scenes.back().conforming = true;
  for (const Scene& scene : scenes) {
    placements.push_back(find_placements(scene));
  }
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    const Scene& scene = scenes[s];
    std::fprintf(stderr, "%s: %d liver triangles, %d instrument triangles\n", scene.name.c_str(),
                 static_cast<int>(scene.liver_triangles.cols()),
                 static_cast<int>(scene.tool_triangles.cols()));
    for (const Placement& placement : placements[s]) {
      std::fprintf(stderr, "  target %4d pairs: %s %.4f%s, %d pairs\n", placement.target,
                   scene.conforming ? "band" : "depth",
                   scene.conforming ? placement.parameter : placement.parameter * 1e3,
                   scene.conforming ? " probe radii" : " mm", placement.pairs);
      const std::string suffix = scene.name + "/target:" + std::to_string(placement.target);
      for (const TreeKind& tree : tree_kinds()) {
        bench::repeated(
            benchmark::RegisterBenchmark(("BM_Frame/" + suffix + "/" + tree.name).c_str(),
                                         [&scene, &placement, &tree](benchmark::State& state) {
                                           run_ours(state, scene, placement, tree.liver,
                                                    tree.tool, tree.batched);
                                         })
                ->Unit(benchmark::kMicrosecond),
            5, 0.2);
      }
      bench::repeated(
          benchmark::RegisterBenchmark(
              ("BM_Frame/" + suffix + "/fcl_aabb").c_str(),
              [&scene, &placement](benchmark::State& state) { run_fcl(state, scene, placement); })
              ->Unit(benchmark::kMicrosecond),
          5, 0.2);
      bench::repeated(
          benchmark::RegisterBenchmark(("BM_Compare/" + suffix).c_str(),
                                       [&scene, &placement](benchmark::State& state) {
                                         run_compare(state, scene, placement);
                                       })
              ->Unit(benchmark::kMicrosecond),
          11, 0.3);
    }
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench::collision
