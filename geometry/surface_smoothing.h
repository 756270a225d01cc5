// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tri_mesh.h"

namespace softbench {

/// Taubin lambda|mu smoothing (Taubin 1995): alternating shrink (lambda > 0) and inflate
/// (mu < -lambda) umbrella steps with uniform weights, which smooths without the shrinkage of
/// plain Laplacian smoothing. Connectivity is unchanged.
void taubin_smooth(TriMesh& surface, int iterations, double lambda = 0.5, double mu = -0.53);

}  // namespace softbench
