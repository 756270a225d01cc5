// SPDX-License-Identifier: MIT
// Mesh-side costs a model or the harness pays once per scene (loading, boundary extraction,
// quality) or per frame (boundary extraction for rendering), on the shipped livers.
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"
#include "scenes/shipped_data.h"

#include <benchmark/benchmark.h>

#include <string>

namespace softbench {
namespace {

const char* const kLivers[] = {"liver.msh", "liver_x4.msh", "liver_x16.msh"};

void set_counters(benchmark::State& state, const MeshData& mesh) {
  state.counters["tets"] = static_cast<double>(mesh.tetrahedra.cols());
  state.counters["tets_per_s"] = benchmark::Counter(
      static_cast<double>(mesh.tetrahedra.cols()) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
}

void register_benchmarks() {
  for (const char* name : kLivers) {
    const std::string file = scenes::shipped_data_file(name).string();
    benchmark::RegisterBenchmark(("BM_ReadAndValidate/" + std::string(name)).c_str(),
                                 [file](benchmark::State& state) {
                                   MeshData mesh;
                                   for (auto _ : state) {
                                     mesh = read_mesh(file);
                                     benchmark::DoNotOptimize(make_tet_mesh(mesh));
                                   }
                                   set_counters(state, mesh);
                                 })
        ->Unit(benchmark::kMillisecond);
    const MeshData mesh = read_mesh(file);
    benchmark::RegisterBenchmark(("BM_BoundaryTriangles/" + std::string(name)).c_str(),
                                 [mesh](benchmark::State& state) {
                                   for (auto _ : state) {
                                     benchmark::DoNotOptimize(boundary_triangles(mesh.tetrahedra));
                                   }
                                   set_counters(state, mesh);
                                 })
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(
        ("BM_TetQuality/" + std::string(name)).c_str(),
        [mesh](benchmark::State& state) {
          for (auto _ : state) {
            benchmark::DoNotOptimize(tet_quality(mesh.vertices, mesh.tetrahedra));
          }
          set_counters(state, mesh);
        })
        ->Unit(benchmark::kMillisecond);
  }
}

const bool kRegistered = (register_benchmarks(), true);

}  // namespace
}  // namespace softbench
