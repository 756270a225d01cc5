// SPDX-License-Identifier: MIT
#include "meshgen/ct_phantom.h"

#include "geometry/mesh_measures.h"
#include "meshgen/segmentation.h"

#include <gtest/gtest.h>

namespace softbench::meshgen {
namespace {

// A coarse phantom keeps these tests fast; the shape does not depend on the voxel size.
PhantomOptions coarse_phantom() {
  PhantomOptions options;
  options.voxel_size = 0.004;
  return options;
}

TEST(LiverPhantom, IsAPureFunctionOfItsSeed) {
  const ScalarGrid a = make_liver_phantom(coarse_phantom());
  const ScalarGrid b = make_liver_phantom(coarse_phantom());
  PhantomOptions other = coarse_phantom();
  other.seed += 1;
  const ScalarGrid c = make_liver_phantom(other);
  EXPECT_EQ(a.values, b.values);
  EXPECT_NE(a.values, c.values);
}

TEST(LiverPhantom, OrganIsAboutTwentyByFifteenByTenCentimetres) {
  const ScalarGrid grid = make_liver_phantom(coarse_phantom());
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(1e9);
  Eigen::Vector3d upper = Eigen::Vector3d::Constant(-1e9);
  for (int k = 0; k < grid.size.z(); ++k) {
    for (int j = 0; j < grid.size.y(); ++j) {
      for (int i = 0; i < grid.size.x(); ++i) {
        if (liver_phantom_implicit(grid.position(i, j, k)) < 0.0) {
          lower = lower.cwiseMin(grid.position(i, j, k));
          upper = upper.cwiseMax(grid.position(i, j, k));
        }
      }
    }
  }
  const Eigen::Vector3d size = upper - lower;
  EXPECT_NEAR(size.x(), 0.20, 0.02);
  EXPECT_NEAR(size.y(), 0.15, 0.02);
  EXPECT_NEAR(size.z(), 0.10, 0.02);
}

TEST(Segmentation, RecoversOneOrganFromNoisyIntensities) {
  PhantomOptions options = coarse_phantom();
  options.noise_sigma = 0.15;  // heavy noise: thresholding alone leaves specks and holes
  const ScalarGrid ct = make_liver_phantom(options);
  ScalarGrid labels = threshold_segment(ct, 0.675f);
  const int removed = remove_islands(labels);
  const int filled = fill_cavities(labels);
  EXPECT_GT(removed, 0);
  EXPECT_GT(filled, 0);

  // Compare with the noise-free truth: misclassified voxels are a small fraction of the organ.
  int organ = 0;
  int wrong = 0;
  for (int k = 0; k < ct.size.z(); ++k) {
    for (int j = 0; j < ct.size.y(); ++j) {
      for (int i = 0; i < ct.size.x(); ++i) {
        const bool truth = liver_phantom_implicit(ct.position(i, j, k)) < 0.0;
        organ += truth;
        wrong += truth != (labels.at(i, j, k) > 0.5f);
      }
    }
  }
  EXPECT_LT(wrong, organ / 10);
}

TEST(Segmentation, RemoveIslandsKeepsOnlyTheLargestComponent) {
  ScalarGrid labels;
  labels.size = {8, 4, 4};
  labels.values.assign(8 * 4 * 4, 0.0f);
  for (int i = 0; i < 3; ++i) {
    labels.at(i, 1, 1) = 1.0f;  // a 3-voxel bar
  }
  labels.at(6, 2, 2) = 1.0f;  // a speck
  EXPECT_EQ(remove_islands(labels), 1);
  EXPECT_EQ(labels.at(6, 2, 2), 0.0f);
  EXPECT_EQ(labels.at(1, 1, 1), 1.0f);
}

TEST(Segmentation, FillCavitiesFillsEnclosedHolesOnly) {
  ScalarGrid labels;
  labels.size = {5, 5, 5};
  labels.values.assign(125, 0.0f);
  for (int k = 1; k < 4; ++k) {
    for (int j = 1; j < 4; ++j) {
      for (int i = 1; i < 4; ++i) {
        labels.at(i, j, k) = 1.0f;
      }
    }
  }
  labels.at(2, 2, 2) = 0.0f;  // a hole inside the cube
  EXPECT_EQ(fill_cavities(labels), 1);
  EXPECT_EQ(labels.at(2, 2, 2), 1.0f);
  EXPECT_EQ(labels.at(0, 0, 0), 0.0f);
}

TEST(Segmentation, GaussianBlurPreservesTheTotalAwayFromTheBorder) {
  ScalarGrid grid;
  grid.size = {21, 21, 21};
  grid.values.assign(21 * 21 * 21, 0.0f);
  grid.at(10, 10, 10) = 1.0f;
  const ScalarGrid blurred = gaussian_blur(grid, 1.5);
  double total = 0.0;
  for (float value : blurred.values) {
    total += value;
  }
  EXPECT_NEAR(total, 1.0, 1e-5);  // float accumulation over ~9k samples
  EXPECT_LT(blurred.at(10, 10, 10), 0.1f);
  EXPECT_FLOAT_EQ(blurred.at(9, 10, 10), blurred.at(11, 10, 10));
}

}  // namespace
}  // namespace softbench::meshgen
