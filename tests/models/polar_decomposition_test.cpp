// SPDX-License-Identifier: MIT
#include "models/corotational_fem/polar_decomposition.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace softbench::corotational_fem {
namespace {

/// R^T R = I and det R = 1 for O(1) entries after a few dozen flops.
constexpr double kRotationRoundoff = 1e-12;
/// A converged quaternion (updates below 1e-13 rad) against the SVD's exact rotation: the
/// remaining error is the size of the last update, amplified by the conditioning of F.
constexpr double kConvergedAgreement = 1e-9;
/// Enough Mueller iterations from the identity for any rotation below ~170 degrees: the error
/// shrinks by about 3x per iteration (the update is 2 sin(e) / (1 + 2 cos(e)) of an error e).
constexpr int kColdStartIterations = 200;
constexpr double kConvergedTolerance = 1e-13;

Eigen::Matrix3d random_rotation(std::mt19937& random, double max_angle) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Vector3d axis =
      Eigen::Vector3d(unit(random), unit(random), unit(random)).normalized();
  return Eigen::AngleAxisd(max_angle * std::abs(unit(random)), axis).toRotationMatrix();
}

/// A symmetric positive definite stretch with eigenvalues in [lo, hi].
Eigen::Matrix3d random_stretch(std::mt19937& random, double lo, double hi) {
  std::uniform_real_distribution<double> eigenvalue(lo, hi);
  const Eigen::Matrix3d frame = random_rotation(random, std::numbers::pi);
  const Eigen::Vector3d values(eigenvalue(random), eigenvalue(random), eigenvalue(random));
  return frame * values.asDiagonal() * frame.transpose();
}

void expect_proper_rotation(const Eigen::Matrix3d& rotation) {
  ASSERT_TRUE(rotation.allFinite());
  EXPECT_TRUE(
      (rotation.transpose() * rotation).isApprox(Eigen::Matrix3d::Identity(), kRotationRoundoff));
  EXPECT_NEAR(rotation.determinant(), 1.0, kRotationRoundoff);
}

TEST(RotationBySvd, IsThePolarRotationOfANonInvertedDeformation) {
  std::mt19937 random(1);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Matrix3d rotation = random_rotation(random, std::numbers::pi);
    const Eigen::Matrix3d stretch = random_stretch(random, 0.2, 3.0);
    const Eigen::Matrix3d found = rotation_by_svd(rotation * stretch);
    expect_proper_rotation(found);
    EXPECT_TRUE(found.isApprox(rotation, kConvergedAgreement)) << "trial " << trial;
  }
}

TEST(RotationBySvd, GivesAProperRotationWithASymmetricStretchForInvertedElements) {
  std::mt19937 random(2);
  std::uniform_real_distribution<double> entry(-2.0, 2.0);
  int inverted = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix3d deformation;
    for (int k = 0; k < 9; ++k) {
      deformation(k) = entry(random);
    }
    inverted += deformation.determinant() < 0.0 ? 1 : 0;
    const Eigen::Matrix3d rotation = rotation_by_svd(deformation);
    expect_proper_rotation(rotation);
    const Eigen::Matrix3d stretch = rotation.transpose() * deformation;
    EXPECT_TRUE(stretch.isApprox(stretch.transpose(), kConvergedAgreement)) << "trial " << trial;
  }
  EXPECT_GT(inverted, 50);  // the sample did exercise the sign fix
}

TEST(RotationBySvd, MovesTheReflectionOntoTheSmallestSingularValue) {
  // F = Q diag(2, 1.5, -0.5): inverted along the third axis. Irving et al.'s R is Q and the
  // stretch diag(2, 1.5, -0.5), not a reflection with an all-positive stretch.
  std::mt19937 random(3);
  const Eigen::Matrix3d rotation = random_rotation(random, 2.5);
  const Eigen::Matrix3d deformation = rotation * Eigen::Vector3d(2.0, 1.5, -0.5).asDiagonal();
  EXPECT_TRUE(rotation_by_svd(deformation).isApprox(rotation, kConvergedAgreement));
}

TEST(RotationBySvd, HandlesCollapsedElements) {
  // A flat element (rank 2: projected onto a plane), a needle (rank 1) and a point (rank 0).
  const Eigen::Vector3d normal = Eigen::Vector3d(1.0, 2.0, 2.0).normalized();
  const Eigen::Matrix3d flat = Eigen::Matrix3d::Identity() - normal * normal.transpose();
  const Eigen::Matrix3d needle = normal * Eigen::Vector3d(0.3, -0.2, 1.0).transpose();
  for (const Eigen::Matrix3d& deformation : {flat, needle, Eigen::Matrix3d::Zero().eval()}) {
    expect_proper_rotation(rotation_by_svd(deformation));
  }
  // Projecting onto a plane does not rotate: R = I, so the element is pushed back along the
  // normal, never inverted through it.
  EXPECT_TRUE(rotation_by_svd(flat).isApprox(Eigen::Matrix3d::Identity(), kConvergedAgreement));
}

TEST(ExtractRotation, AgreesWithSvdOnNonInvertedDeformationsFromAColdStart) {
  std::mt19937 random(4);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Matrix3d deformation =
        random_rotation(random, 0.9 * std::numbers::pi) * random_stretch(random, 0.3, 2.5);
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
    const int iterations =
        extract_rotation(deformation, rotation, kColdStartIterations, kConvergedTolerance);
    EXPECT_LT(iterations, kColdStartIterations) << "trial " << trial;
    expect_proper_rotation(rotation.toRotationMatrix());
    EXPECT_TRUE(
        rotation.toRotationMatrix().isApprox(rotation_by_svd(deformation), kConvergedAgreement))
        << "trial " << trial;
  }
}

TEST(ExtractRotation, FindsTheSignFixedRotationOfAnInvertedElement) {
  // The maximiser of tr(R^T F) over proper rotations is Irving et al.'s R.
  std::mt19937 random(5);
  const Eigen::Matrix3d rotation = random_rotation(random, 1.0);
  const Eigen::Matrix3d deformation = rotation * Eigen::Vector3d(2.0, 1.5, -0.5).asDiagonal();
  Eigen::Quaterniond found = Eigen::Quaterniond::Identity();
  extract_rotation(deformation, found, kColdStartIterations, kConvergedTolerance);
  EXPECT_TRUE(found.toRotationMatrix().isApprox(rotation_by_svd(deformation), kConvergedAgreement));
}

TEST(ExtractRotation, StopsAtOnceWhenWarmStartedFromTheAnswer) {
  std::mt19937 random(6);
  const Eigen::Matrix3d rotation = random_rotation(random, 2.0);
  const Eigen::Matrix3d deformation = rotation * random_stretch(random, 0.5, 1.5);
  Eigen::Quaterniond warm(rotation);
  EXPECT_EQ(extract_rotation(deformation, warm, 10, 1e-6), 0);
  EXPECT_TRUE(warm.toRotationMatrix().isApprox(rotation, kRotationRoundoff));
}

TEST(ExtractRotation, TracksASteadilyRotatingElementWithTwoIterationsPerStep) {
  // 2 degrees per step about a fixed axis, warm-started, 2 updates per step: the lag settles at
  // about a tenth of the per-step angle (error e -> (e + step) / 9 per step).
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -1.0, 0.5).normalized();
  const double step = 2.0 * std::numbers::pi / 180.0;
  std::mt19937 random(7);
  const Eigen::Matrix3d stretch = random_stretch(random, 0.8, 1.2);
  Eigen::Quaterniond tracked = Eigen::Quaterniond::Identity();
  for (int n = 1; n <= 100; ++n) {
    const Eigen::Matrix3d rotation = Eigen::AngleAxisd(n * step, axis).toRotationMatrix();
    extract_rotation(rotation * stretch, tracked, 2, 1e-12);
    const double lag = Eigen::AngleAxisd(tracked.toRotationMatrix() * rotation.transpose()).angle();
    ASSERT_LT(lag, 0.25 * step) << "step " << n;
  }
}

TEST(ExtractRotations, MatchesTheIterationOneElementAtATime) {
  // 37 elements: four full batches of kRotationLanes (8) and a partial one. A tolerance below reach keeps every
  // element iterating, so the batched and the scalar iteration take the same steps.
  std::mt19937 random(8);
  std::vector<Eigen::Matrix3d> deformations;
  std::vector<Eigen::Quaterniond> batched;
  for (int k = 0; k < 37; ++k) {
    deformations.push_back(random_rotation(random, 2.5) * random_stretch(random, 0.5, 1.5));
    batched.emplace_back(random_rotation(random, 0.5));
  }
  std::vector<Eigen::Quaterniond> single = batched;
  std::vector<Eigen::Matrix3d> matrices(deformations.size());
  constexpr int kIterations = 5;
  extract_rotations(deformations, batched, matrices, kIterations, 1e-300);
  for (std::size_t k = 0; k < deformations.size(); ++k) {
    extract_rotation(deformations[k], single[k], kIterations, 1e-300);
    EXPECT_TRUE(batched[k].coeffs().isApprox(single[k].coeffs(), kRotationRoundoff)) << k;
    EXPECT_TRUE(matrices[k].isApprox(batched[k].toRotationMatrix(), kRotationRoundoff)) << k;
  }
}

TEST(ExtractRotations, StopsABatchOnlyWhenAllItsElementsConverged) {
  // Element 0 starts at its answer, element 1 far from it: the batch keeps iterating for
  // element 1, and element 0 stays at its answer (its updates are zero to round-off).
  std::mt19937 random(9);
  const Eigen::Matrix3d rotation = random_rotation(random, 2.0);
  const std::vector<Eigen::Matrix3d> deformations{rotation, rotation};
  std::vector<Eigen::Quaterniond> rotations{Eigen::Quaterniond(rotation),
                                            Eigen::Quaterniond::Identity()};
  std::vector<Eigen::Matrix3d> matrices(2);
  extract_rotations(deformations, rotations, matrices, kColdStartIterations, kConvergedTolerance);
  EXPECT_TRUE(matrices[0].isApprox(rotation, kRotationRoundoff));
  EXPECT_TRUE(matrices[1].isApprox(rotation, kConvergedAgreement));
}

TEST(ExtractRotation, KeepsItsRotationForACollapsedOrNonFiniteElement) {
  const Eigen::Quaterniond start(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()));
  Eigen::Quaterniond rotation = start;
  EXPECT_EQ(extract_rotation(Eigen::Matrix3d::Zero(), rotation, 10, 1e-9), 0);
  EXPECT_TRUE(rotation.coeffs().isApprox(start.coeffs(), kRotationRoundoff));
  const Eigen::Matrix3d nan = Eigen::Matrix3d::Constant(std::nan(""));
  EXPECT_EQ(extract_rotation(nan, rotation, 10, 1e-9), 0);
  EXPECT_TRUE(rotation.coeffs().allFinite());
}

}  // namespace
}  // namespace softbench::corotational_fem
