// SPDX-License-Identifier: MIT
// SampleClearance's bounds hold against exact queries while a closed surface deforms and moves
// and a rigid instrument moves through it, over many small states.
#include "collision/sample_clearance.h"

#include "collision/mesh_distance.h"
#include "tests/collision/bvh_test_meshes.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace softbench::collision {
namespace {

TEST(SampleClearance, ItsBoundsHoldWhileTheSurfaceAndTheInstrumentMove) {
  std::mt19937 rng(31);
  // The tissue: a lumpy sphere of radius ~1 that breathes and drifts. The instrument: a small
  // box whose vertices are its samples, swept through the sphere and out.
  TriMesh tissue = test::icosphere(2, 1.0);
  test::perturb_radially(tissue, 0.1, rng);
  const TriMesh tool = test::box_surface(2, Eigen::Vector3d(0.3, 0.2, 0.4));
  MeshDistance distance(tissue.vertices, tissue.triangles);
  SampleClearance clearance(tool.vertices.cols(), tool.vertices);

  int known = 0, queried = 0, inside_checks = 0, far_checks = 0;
  constexpr int kStates = 400;
  for (int state = 0; state < kStates; ++state) {
    const double t = static_cast<double>(state) / kStates;
    const Eigen::Matrix3Xd surface =
        (1.0 + 0.05 * std::sin(12.0 * t)) * test::jitter(tissue.vertices, 0.002, rng)
        + Eigen::Vector3d(0.1 * t, 0.0, 0.0).replicate(1, tissue.vertices.cols());
    distance.update(surface);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translate(Eigen::Vector3d(-2.0 + 4.0 * t, 0.05, -0.1));
    pose.rotate(Eigen::AngleAxisd(3.0 * t, Eigen::Vector3d::UnitY()));
    clearance.advance(surface, pose);
    for (Eigen::Index i = 0; i < tool.vertices.cols(); ++i) {
      const double exact =
          distance.nearest(pose * Eigen::Vector3d(tool.vertices.col(i))).signed_distance;
      // Probe the bounds at several distances before refreshing some of them, as the contact
      // does (it queries only what the bounds leave open).
      for (const double d : {0.0, 0.01, 0.1, 0.5}) {
        if (clearance.outside_by(i, d)) {
          ++known;
          EXPECT_GE(exact, d) << "state " << state << " sample " << i;
        }
        if (clearance.inside_by(i, d)) {
          ++inside_checks;
          EXPECT_LT(exact, -d) << "state " << state << " sample " << i;
        }
        if (clearance.far_by(i, d)) {
          ++far_checks;
          EXPECT_GT(std::abs(exact), d) << "state " << state << " sample " << i;
        }
      }
      if (!clearance.outside_by(i, 0.1) && !clearance.inside_by(i, 0.1)
          && !clearance.far_by(i, 0.1)) {
        // Half the samples as a query bounded at 0.3 records them (nearest_within): farther
        // than that, its side unknown.
        if (i % 2 == 0 && std::abs(exact) >= 0.3) {
          clearance.record_far(i, 0.3);
        } else {
          clearance.record(i, exact, -1);
        }
        ++queried;
      }
    }
  }
  // The bounds spared most queries, and the inside ones were exercised too.
  EXPECT_GT(known, queried);
  EXPECT_GT(inside_checks, 100);
  EXPECT_GT(far_checks, 100);
}

// Tissue carried along by the tool (pressed ahead of a probe, pulled by a grasp) keeps the
// clearance it had: the bound spends the surface's and the tool's moves relative to the tool's
// own shift, not their sum (which would spend twice the shift a state). Turning as well, the
// tool spends only what the turn moves its vertices.
TEST(SampleClearance, TissueCarriedAlongByTheToolKeepsItsClearance) {
  const TriMesh tissue = test::icosphere(2, 1.0);
  // Box corners within 0.36 of the tool's z axis, its bottom 0.5 above the unit sphere.
  const TriMesh tool = test::box_surface(2, Eigen::Vector3d(0.3, 0.2, 0.4));
  const Eigen::Vector3d start(0.0, 0.0, 1.5);
  constexpr double kTurn = 0.01;  // rad a state
  constexpr int kStates = 50;
  for (const double turn : {0.0, kTurn}) {
    SCOPED_TRACE(turn);
    MeshDistance distance(tissue.vertices, tissue.triangles);
    SampleClearance clearance(tool.vertices.cols(), tool.vertices);
    std::vector<double> recorded(static_cast<std::size_t>(tool.vertices.cols()));
    for (int state = 0; state < kStates; ++state) {
      const Eigen::Vector3d shift(0.02 * state, -0.01 * state, 0.0);
      const Eigen::Matrix3Xd surface = tissue.vertices.colwise() + shift;
      distance.update(surface);
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.translate(start + shift);
      pose.rotate(Eigen::AngleAxisd(turn * state, Eigen::Vector3d::UnitZ()));
      clearance.advance(surface, pose);
      for (Eigen::Index i = 0; i < tool.vertices.cols(); ++i) {
        const double exact =
            distance.nearest(pose * Eigen::Vector3d(tool.vertices.col(i))).signed_distance;
        if (state == 0) {
          clearance.record(i, exact, -1);
          recorded[static_cast<std::size_t>(i)] = exact;
          continue;
        }
        for (const double d : {0.0, 0.1, 0.3}) {
          if (clearance.outside_by(i, d)) {
            EXPECT_GE(exact, d) << "state " << state << " sample " << i;
          }
        }
        // Spent: round-off alone without the turn; with it, at most 0.36 kTurn a state.
        const double spent = turn == 0.0 ? 1e-9 : 0.36 * kTurn * state * 1.01;
        EXPECT_TRUE(clearance.outside_by(i, recorded[static_cast<std::size_t>(i)] - spent))
            << "state " << state << " sample " << i;
      }
    }
  }
}

TEST(SampleClearance, KnowsNothingBeforeAQueryOrAfterTheSurfaceChangesSize) {
  const TriMesh tool = test::box_surface(1);
  SampleClearance clearance(tool.vertices.cols(), tool.vertices);
  const Eigen::Matrix3Xd surface = Eigen::Matrix3Xd::Zero(3, 4);
  clearance.advance(surface, Eigen::Isometry3d::Identity());
  EXPECT_FALSE(clearance.outside_by(0, 0.0));
  EXPECT_FALSE(clearance.inside_by(0, 0.0));
  EXPECT_FALSE(clearance.far_by(0, 0.0));
  EXPECT_EQ(clearance.hint(0), -1);  // no triangle found yet
  // Far by 0.4 on a side not known: neither side is claimed.
  clearance.record_far(0, 0.4);
  EXPECT_TRUE(clearance.far_by(0, 0.39));
  EXPECT_FALSE(clearance.outside_by(0, 0.0));
  EXPECT_FALSE(clearance.inside_by(0, 0.0));
  clearance.record(0, 0.5, 3);
  EXPECT_EQ(clearance.hint(0), 3);
  EXPECT_TRUE(clearance.outside_by(0, 0.5));
  EXPECT_FALSE(clearance.outside_by(0, 0.6));
  // A surface move of 0.2 lowers the bound by at least that.
  Eigen::Matrix3Xd moved = surface;
  moved(0, 1) = 0.2;
  clearance.advance(moved, Eigen::Isometry3d::Identity());
  EXPECT_FALSE(clearance.outside_by(0, 0.31));
  EXPECT_TRUE(clearance.outside_by(0, 0.29));
  // Another surface (a different vertex count): no earlier state to measure moves from.
  clearance.advance(Eigen::Matrix3Xd::Zero(3, 5), Eigen::Isometry3d::Identity());
  EXPECT_FALSE(clearance.outside_by(0, 0.0));
  EXPECT_EQ(clearance.hint(0), -1);  // nor a triangle of it
}

}  // namespace
}  // namespace softbench::collision
