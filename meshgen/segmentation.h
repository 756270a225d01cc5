// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/marching_cubes.h"

namespace softbench::meshgen {

// Segmentation of a CT volume into an organ label, the steps the thesis does in Amira (section
// 2.5.3): threshold, "remove islands", fill, "smooth label". Labels are ScalarGrids holding 0
// (outside) or 1 (inside), so the smoothed label feeds marching cubes at iso-value 0.5.

/// 1 where the intensity is above `threshold`, else 0.
ScalarGrid threshold_segment(const ScalarGrid& intensity, float threshold);

/// Keeps only the largest 6-connected inside component (noise specks outside the organ go).
/// Returns the number of voxels removed.
int remove_islands(ScalarGrid& labels);

/// Marks as inside every outside region that does not reach the grid border (noise holes in the
/// organ). Returns the number of voxels filled.
int fill_cavities(ScalarGrid& labels);

/// Separable Gaussian blur with standard deviation `sigma_voxels` (kernel cut at 3 sigma,
/// clamped at the border). On a label it gives a smooth 0..1 field whose 0.5 level set is a
/// smoothed organ boundary, free of the voxel staircase.
ScalarGrid gaussian_blur(const ScalarGrid& grid, double sigma_voxels);

}  // namespace softbench::meshgen
