// SPDX-License-Identifier: MIT
#include "meshgen/liver_pipeline.h"

#include "geometry/marching_cubes.h"
#include "geometry/surface_smoothing.h"
#include "meshgen/segmentation.h"
#include "meshgen/surface_simplification.h"

namespace softbench::meshgen {

std::vector<LiverResolution> default_liver_resolutions() {
  // Tuned so the base mesh is thesis-sized (its liver: 725 surface vertices; 1206 vertices and
  // 4230 tets in all) and the refinements have about 4x and 16x its tets. Surface vertex counts
  // grow like tets^(2/3) so that tets stay well shaped near the boundary.
  const auto resolution = [](const char* name, int surface_vertices, double max_volume) {
    LiverResolution result{name, surface_vertices, {}};
    result.tets.max_volume = max_volume;
    return result;
  };
  return {resolution("liver", 800, 9.0e-7), resolution("liver_x4", 2100, 1.9e-7),
          resolution("liver_x16", 5600, 4.4e-8)};
}

LiverPipelineResult run_liver_pipeline(const LiverPipelineOptions& options) {
  LiverPipelineResult result;
  const ScalarGrid ct = make_liver_phantom(options.phantom);
  result.stats.grid_size = ct.size;

  ScalarGrid labels = threshold_segment(ct, options.threshold);
  result.stats.islands_removed = remove_islands(labels);
  result.stats.cavities_filled = fill_cavities(labels);
  const ScalarGrid smooth_labels = gaussian_blur(labels, options.label_blur_sigma);

  TriMesh surface = marching_cubes(smooth_labels, 0.5f);
  result.stats.marching_cubes_vertices = surface.num_vertices();
  result.stats.marching_cubes_triangles = surface.num_triangles();
  taubin_smooth(surface, options.taubin_iterations);
  result.smoothed_surface = surface;

  const std::vector<LiverResolution> resolutions =
      options.resolutions.empty() ? default_liver_resolutions() : options.resolutions;
  for (const LiverResolution& resolution : resolutions) {
    LiverMeshes meshes;
    meshes.name = resolution.name;
    meshes.surface = simplify_surface(surface, resolution.surface_vertices);
    meshes.volume = tetrahedralize(meshes.surface, resolution.tets);
    meshes.volume.source = resolution.name;
    result.meshes.push_back(std::move(meshes));
  }
  return result;
}

}  // namespace softbench::meshgen
