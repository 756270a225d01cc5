// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"
#include "geometry/tri_mesh.h"
#include "meshgen/ct_phantom.h"
#include "meshgen/tetrahedralize.h"

#include <string>
#include <vector>

namespace softbench::meshgen {

/// One resolution of the liver: how far to simplify the surface and how to fill it with tets.
struct LiverResolution {
  std::string name;            ///< file stem, e.g. "liver" or "liver_x4"
  int surface_vertices = 800;  ///< target after simplification
  TetrahedralizeOptions tets;
};

/// The thesis's chapter-2 pipeline on the synthetic CT phantom: threshold segmentation, island
/// removal and cavity filling, label smoothing, marching cubes, Taubin smoothing, simplification,
/// TetGen. Deterministic for a given seed.
struct LiverPipelineOptions {
  PhantomOptions phantom;
  float threshold = 0.675f;       ///< halfway between tissue and organ intensity
  double label_blur_sigma = 1.0;  ///< voxels ("smooth label")
  int taubin_iterations = 20;
  std::vector<LiverResolution> resolutions;  ///< empty: default_liver_resolutions()
};

/// The shipped set: the thesis-sized liver (~1200 vertices / 4200 tets) and two refinements
/// with about 4x and 16x its tets, for scaling benchmarks.
std::vector<LiverResolution> default_liver_resolutions();

/// Per-stage figures, written next to the meshes so a reader sees how they were made.
struct LiverPipelineStats {
  Eigen::Vector3i grid_size;
  int islands_removed = 0;
  int cavities_filled = 0;
  int marching_cubes_vertices = 0;
  int marching_cubes_triangles = 0;
};

struct LiverMeshes {
  std::string name;
  TriMesh surface;  ///< the simplified surface TetGen was given
  MeshData volume;  ///< vertices, positive tets and boundary triangles
};

struct LiverPipelineResult {
  LiverPipelineStats stats;
  TriMesh smoothed_surface;         ///< after marching cubes and Taubin, before simplification
  std::vector<LiverMeshes> meshes;  ///< one per resolution, in order
};

LiverPipelineResult run_liver_pipeline(const LiverPipelineOptions& options = {});

}  // namespace softbench::meshgen
