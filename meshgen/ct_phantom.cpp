// SPDX-License-Identifier: MIT
#include "meshgen/ct_phantom.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

namespace softbench::meshgen {
namespace {

struct Lobe {
  Eigen::Vector3d centre;  // m
  Eigen::Vector3d radii;   // m
};

// x: patient left (-) to right (+), y: posterior (-) to anterior (+), z: inferior to superior.
// The right lobe dominates; the left lobe is thinner and tapers towards the left.
const std::array<Lobe, 3> kLobes = {{
    {{0.035, 0.000, 0.000}, {0.066, 0.070, 0.050}},    // right lobe
    {{-0.050, 0.014, 0.012}, {0.052, 0.045, 0.026}},   // left lobe
    {{-0.004, -0.028, 0.006}, {0.032, 0.028, 0.030}},  // caudate bulge, posterior
}};

// Softness of the union (m): larger blends the lobes into each other more gradually.
constexpr double kBlend = 0.008;

double ellipsoid_implicit(const Lobe& lobe, const Eigen::Vector3d& point) {
  // Scaled radial distance minus one, multiplied by the smallest radius so the value is roughly
  // a distance in metres near the surface (needed for a metric partial-volume blur).
  const double scaled = (point - lobe.centre).cwiseQuotient(lobe.radii).norm();
  return (scaled - 1.0) * lobe.radii.minCoeff();
}

// Box-Muller on mt19937's raw output: std::normal_distribution's algorithm is unspecified, so a
// standard-library change could otherwise change the committed liver.
class GaussianNoise {
 public:
  explicit GaussianNoise(std::uint32_t seed) : engine_(seed) {}
  double next() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = (static_cast<double>(engine_()) + 1.0) / 4294967297.0;  // (0, 1]
    const double u2 = static_cast<double>(engine_()) / 4294967296.0;          // [0, 1)
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(2.0 * std::numbers::pi * u2);
    has_spare_ = true;
    return radius * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::mt19937 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace

double liver_phantom_implicit(const Eigen::Vector3d& point) {
  // Smooth minimum (log-sum-exp) of the lobes: a union without creases where lobes meet.
  double sum = 0.0;
  for (const Lobe& lobe : kLobes) {
    sum += std::exp(-ellipsoid_implicit(lobe, point) / kBlend);
  }
  return -kBlend * std::log(sum);
}

ScalarGrid make_liver_phantom(const PhantomOptions& options) {
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(1e9);
  Eigen::Vector3d upper = Eigen::Vector3d::Constant(-1e9);
  for (const Lobe& lobe : kLobes) {
    lower = lower.cwiseMin(lobe.centre - lobe.radii);
    upper = upper.cwiseMax(lobe.centre + lobe.radii);
  }
  lower.array() -= options.margin;
  upper.array() += options.margin;

  ScalarGrid grid;
  grid.origin = lower;
  grid.spacing = Eigen::Vector3d::Constant(options.voxel_size);
  grid.size = ((upper - lower) / options.voxel_size).array().ceil().cast<int>() + 1;
  grid.values.resize(static_cast<std::size_t>(grid.size.prod()));

  GaussianNoise noise(options.seed);
  const double contrast = options.organ_intensity - options.tissue_intensity;
  for (int k = 0; k < grid.size.z(); ++k) {
    for (int j = 0; j < grid.size.y(); ++j) {
      for (int i = 0; i < grid.size.x(); ++i) {
        // Partial volume: the fraction of a voxel inside the organ ramps over one voxel width.
        const double distance = liver_phantom_implicit(grid.position(i, j, k));
        const double inside_fraction = std::clamp(0.5 - distance / options.voxel_size, 0.0, 1.0);
        grid.at(i, j, k) = static_cast<float>(options.tissue_intensity + contrast * inside_fraction
                                              + options.noise_sigma * noise.next());
      }
    }
  }
  return grid;
}

}  // namespace softbench::meshgen
