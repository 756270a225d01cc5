// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/marching_cubes.h"

#include <cstdint>

namespace softbench::meshgen {

/// A synthetic CT volume of a liver-like organ, standing in for the thesis's 200 Visible Human
/// slices (section 2.5), which cannot ship here. The organ is a smooth union of ellipsoidal lobes
/// (a large right lobe, a tapering left lobe, a caudate bulge) about 20 x 15 x 10 cm, in metres,
/// centred near the origin. Partial-volume blur at the organ boundary and Gaussian noise make the
/// threshold segmentation do real work, as on CT.
struct PhantomOptions {
  double voxel_size = 0.002;       ///< m; the thesis's slices are 1 mm apart, 2 mm keeps it fast
  double organ_intensity = 1.0;    ///< arbitrary units (liver parenchyma ~ 60 HU)
  double tissue_intensity = 0.35;  ///< surrounding tissue; contrast is the difference
  double noise_sigma = 0.08;       ///< std. dev. of the additive Gaussian noise
  double margin = 0.012;           ///< m of tissue around the organ's bounding box
  std::uint32_t seed = 20261122;   ///< the noise is a pure function of this seed
};

/// Signed, roughly metric implicit function of the organ: negative inside, positive outside.
double liver_phantom_implicit(const Eigen::Vector3d& point);

/// Samples the phantom: intensity = tissue + contrast * partial-volume fraction + noise.
ScalarGrid make_liver_phantom(const PhantomOptions& options = {});

}  // namespace softbench::meshgen
