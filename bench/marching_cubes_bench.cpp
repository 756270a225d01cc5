// SPDX-License-Identifier: MIT
#include "geometry/marching_cubes.h"
#include "geometry/surface_smoothing.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

// Marching cubes on a 200 x 150 x 100 grid (about a CT volume's size after cropping): a smooth
// ellipsoid (surface through ~5% of the cells) and random noise (surface through most cells,
// every case and every ambiguous face), with and without normals; then Taubin smoothing of the
// ellipsoid's surface.
namespace softbench {
namespace {

ScalarGrid ct_sized_grid() {
  ScalarGrid grid;
  grid.size = {200, 150, 100};
  grid.spacing = {0.5e-3, 0.5e-3, 0.8e-3};
  grid.values.resize(static_cast<std::size_t>(grid.size.prod()));
  return grid;
}

ScalarGrid ellipsoid_grid() {
  ScalarGrid grid = ct_sized_grid();
  const Eigen::Vector3d centre = 0.5 * (grid.size.cast<double>() - Eigen::Vector3d::Ones());
  const Eigen::Vector3d semi_axes = 0.45 * grid.size.cast<double>();
  for (int k = 0; k < grid.size.z(); ++k) {
    for (int j = 0; j < grid.size.y(); ++j) {
      for (int i = 0; i < grid.size.x(); ++i) {
        const Eigen::Vector3d x = (Eigen::Vector3d(i, j, k) - centre).cwiseQuotient(semi_axes);
        grid.at(i, j, k) = static_cast<float>(1.0 - x.norm());
      }
    }
  }
  return grid;
}

ScalarGrid noise_grid() {
  ScalarGrid grid = ct_sized_grid();
  std::mt19937 random(1);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  for (float& v : grid.values) {
    v = value(random);
  }
  return grid;
}

void BM_MarchingCubesEllipsoid(benchmark::State& state) {
  const ScalarGrid grid = ellipsoid_grid();
  const bool with_normals = state.range(0) != 0;
  Eigen::Matrix3Xd normals;
  for (auto _ : state) {
    TriMesh mesh = marching_cubes(grid, 0.0f, with_normals ? &normals : nullptr);
    benchmark::DoNotOptimize(mesh.vertices.data());
    state.counters["triangles"] = mesh.num_triangles();
  }
}
BENCHMARK(BM_MarchingCubesEllipsoid)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_MarchingCubesNoise(benchmark::State& state) {
  const ScalarGrid grid = noise_grid();
  for (auto _ : state) {
    TriMesh mesh = marching_cubes(grid, 0.0f);
    benchmark::DoNotOptimize(mesh.vertices.data());
    state.counters["triangles"] = mesh.num_triangles();
  }
}
BENCHMARK(BM_MarchingCubesNoise)->Unit(benchmark::kMillisecond);

void BM_TaubinSmoothEllipsoid(benchmark::State& state) {
  const TriMesh original = marching_cubes(ellipsoid_grid(), 0.0f);
  for (auto _ : state) {
    TriMesh mesh = original;
    taubin_smooth(mesh, 10);
    benchmark::DoNotOptimize(mesh.vertices.data());
  }
  state.counters["vertices"] = original.num_vertices();
}
BENCHMARK(BM_TaubinSmoothEllipsoid)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace softbench
