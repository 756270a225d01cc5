// SPDX-License-Identifier: MIT
#include "geometry/mesh_validation.h"
#include "models/shape_matching/cluster_matching.h"
#include "models/shape_matching/clusters.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <vector>

namespace softbench::shape_matching {
namespace {

/// A 20 x 12 x 12 cm box of 10 x 6 x 6 cells: 539 vertices on a regular grid.
const Eigen::Matrix3Xd& grid() {
  static const Eigen::Matrix3Xd points =
      make_tet_mesh(test::box_tets(10, 6, 6, 0.20, 0.12, 0.12)).rest_positions();
  return points;
}

/// 2000 points uniformly in the unit cube, from a fixed seed.
const Eigen::Matrix3Xd& random_cloud() {
  static const Eigen::Matrix3Xd points = [] {
    std::mt19937 generator(96);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Eigen::Matrix3Xd result(3, 2000);
    for (Eigen::Index i = 0; i < result.cols(); ++i) {
      result.col(i) = Eigen::Vector3d(unit(generator), unit(generator), unit(generator));
    }
    return result;
  }();
  return points;
}

/// How many clusters hold each particle.
std::vector<int> memberships_per_particle(const Clusters& clusters, int num_particles) {
  std::vector<int> count(static_cast<std::size_t>(num_particles), 0);
  for (const int particle : clusters.members) {
    ++count[static_cast<std::size_t>(particle)];
  }
  return count;
}

void expect_well_formed(const Clusters& clusters, int num_particles) {
  ASSERT_EQ(clusters.offsets.size(), clusters.seeds.size() + 1);
  EXPECT_EQ(clusters.offsets.front(), 0);
  EXPECT_EQ(clusters.offsets.back(), static_cast<int>(clusters.members.size()));
  for (int k = 0; k < clusters.count(); ++k) {
    const std::span<const int> members = clusters.members_of(k);
    EXPECT_FALSE(members.empty()) << "cluster " << k;
    EXPECT_TRUE(std::is_sorted(members.begin(), members.end()));
    EXPECT_EQ(std::adjacent_find(members.begin(), members.end()), members.end());  // no repeats
    // Its seed is a member.
    EXPECT_TRUE(std::binary_search(members.begin(), members.end(),
                                   clusters.seeds[static_cast<std::size_t>(k)]));
    for (const int particle : members) {
      EXPECT_GE(particle, 0);
      EXPECT_LT(particle, num_particles);
    }
  }
}

TEST(ShapeMatchingClusters, EveryParticleIsInAtLeastOneCluster) {
  for (const Eigen::Matrix3Xd* points : {&grid(), &random_cloud()}) {
    const int num_particles = static_cast<int>(points->cols());
    for (const int count : {2, 8, 50}) {
      for (const int size : {4, 20, 96}) {
        const Clusters clusters = build_clusters(*points, {count, 0.0, size});
        expect_well_formed(clusters, num_particles);
        const std::vector<int> per_particle = memberships_per_particle(clusters, num_particles);
        EXPECT_EQ(*std::min_element(per_particle.begin(), per_particle.end()) > 0, true)
            << count << " clusters of " << size;
      }
    }
  }
}

TEST(ShapeMatchingClusters, AverageSizeIsNearTheTarget) {
  // The radius gives exactly count * target (seed, particle) pairs within it, plus ties at the
  // radius and the particles in no region adopted by their nearest seed: a few percent more
  // when the clusters overlap (count * target >= 2 * #particles, as the thesis's 50 x 96 on
  // 1215 vertices). With less overlap, covering every particle needs more memberships.
  constexpr double kSizeTolerance = 0.10;
  const std::pair<const Eigen::Matrix3Xd*, int> cases[] = {
      {&grid(), 12}, {&grid(), 50}, {&random_cloud(), 50}, {&random_cloud(), 100}};
  for (const auto& [points, count] : cases) {
    ASSERT_GE(count * 96, 2 * points->cols());
    const Clusters clusters = build_clusters(*points, {count, 0.0, 96});
    const double mean = static_cast<double>(clusters.members.size()) / clusters.count();
    EXPECT_GE(mean, 96.0) << count;
    EXPECT_LE(mean, 96.0 * (1.0 + kSizeTolerance)) << count;
  }
}

/// Membership compares squared distances with the squared radius; a distance and the radius
/// (square roots) can round differently by an ulp or two on a grid, where many distances tie.
constexpr double kRadiusRoundoff = 1e-12;

TEST(ShapeMatchingClusters, MembersAreWithinTheRadiusOfTheirSeedOrHaveNoCloserRegion) {
  const Eigen::Matrix3Xd& points = grid();
  const Clusters clusters = build_clusters(points, {20, 0.0, 40});
  ASSERT_GT(clusters.radius, 0.0);
  ASSERT_TRUE(std::isfinite(clusters.radius));
  const std::vector<int> per_particle =
      memberships_per_particle(clusters, static_cast<int>(points.cols()));
  for (int k = 0; k < clusters.count(); ++k) {
    const Eigen::Vector3d seed = points.col(clusters.seeds[static_cast<std::size_t>(k)]);
    for (const int particle : clusters.members_of(k)) {
      const double distance = (points.col(particle) - seed).norm();
      if (distance > clusters.radius * (1.0 + kRadiusRoundoff)) {
        // Adopted: in no region, so in this cluster only.
        EXPECT_EQ(per_particle[static_cast<std::size_t>(particle)], 1) << particle;
      }
    }
  }
  // And every particle within the radius of a seed is in that seed's cluster.
  for (int k = 0; k < clusters.count(); ++k) {
    const Eigen::Vector3d seed = points.col(clusters.seeds[static_cast<std::size_t>(k)]);
    const std::set<int> members(clusters.members_of(k).begin(), clusters.members_of(k).end());
    for (int i = 0; i < points.cols(); ++i) {
      if ((points.col(i) - seed).norm() < clusters.radius * (1.0 - kRadiusRoundoff)) {
        EXPECT_EQ(members.count(i), 1U) << "particle " << i << " cluster " << k;
      }
    }
  }
}

TEST(ShapeMatchingClusters, AGivenRadiusIsUsedAsIs) {
  const Clusters clusters = build_clusters(grid(), {8, 0.05, 96});
  EXPECT_EQ(clusters.radius, 0.05);
  expect_well_formed(clusters, static_cast<int>(grid().cols()));
}

TEST(ShapeMatchingClusters, ConstructionIsDeterministic) {
  const Clusters first = build_clusters(random_cloud(), {32, 0.0, 96});
  const Clusters second = build_clusters(random_cloud(), {32, 0.0, 96});
  EXPECT_EQ(first.seeds, second.seeds);
  EXPECT_EQ(first.offsets, second.offsets);
  EXPECT_EQ(first.members, second.members);
  EXPECT_EQ(first.radius, second.radius);
}

TEST(ShapeMatchingClusters, SeedsAreFarthestPointSamples) {
  const Eigen::Matrix3Xd& points = random_cloud();
  const std::vector<int> seeds = farthest_point_seeds(points, 10);
  ASSERT_EQ(seeds.size(), 10U);
  // The first is the point farthest from the centroid.
  const Eigen::Vector3d centroid = points.rowwise().mean();
  Eigen::Index farthest = 0;
  (points.colwise() - centroid).colwise().squaredNorm().maxCoeff(&farthest);
  EXPECT_EQ(seeds.front(), farthest);
  // Each next one is the point farthest from those before it.
  for (std::size_t s = 1; s < seeds.size(); ++s) {
    const auto distance_to_chosen = [&](Eigen::Index i) {
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t t = 0; t < s; ++t) {
        nearest = std::min(nearest, (points.col(i) - points.col(seeds[t])).norm());
      }
      return nearest;
    };
    const double chosen = distance_to_chosen(seeds[s]);
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      ASSERT_LE(distance_to_chosen(i), chosen) << "seed " << s;
    }
  }
  // Distinct.
  EXPECT_EQ(std::set<int>(seeds.begin(), seeds.end()).size(), seeds.size());
}

TEST(ShapeMatchingClusters, OneClusterHoldsEveryParticle) {
  const Clusters clusters = build_clusters(grid(), {1, 0.0, 96});
  ASSERT_EQ(clusters.count(), 1);
  EXPECT_EQ(clusters.members.size(), static_cast<std::size_t>(grid().cols()));
  EXPECT_TRUE(std::isinf(clusters.radius));
}

TEST(ShapeMatchingClusters, TheCountIsClampedToTheParticles) {
  const Eigen::Matrix3Xd points = grid().leftCols(12);
  const Clusters clusters = build_clusters(points, {50, 0.0, 96});
  EXPECT_EQ(clusters.count(), 12);
  expect_well_formed(clusters, 12);
  // 96 particles wanted, 12 there: every cluster holds all.
  for (int k = 0; k < clusters.count(); ++k) {
    EXPECT_EQ(clusters.members_of(k).size(), 12U);
  }
}

TEST(ShapeMatchingClusters, TheMatcherListsEachParticlesMembershipsInClusterOrder) {
  const Clusters clusters = build_clusters(grid(), {8, 0.0, 96});
  const Eigen::VectorXd masses = Eigen::VectorXd::Ones(grid().cols());
  const ClusterMatcher matcher(grid(), masses, clusters, ShapeMatchingParams{});
  EXPECT_EQ(matcher.num_clusters(), 8);
  EXPECT_EQ(matcher.num_memberships(), static_cast<int>(clusters.members.size()));
  EXPECT_EQ(matcher.basis_size(), 9);
  for (int m = 0; m < matcher.num_memberships(); ++m) {
    const int k = matcher.cluster_of_membership(m);
    ASSERT_GE(m, matcher.cluster_begin(k));
    ASSERT_LT(m, matcher.cluster_end(k));
    EXPECT_EQ(matcher.particle_of_membership(m), clusters.members[static_cast<std::size_t>(m)]);
  }
}

TEST(ShapeMatchingClusters, EachParticlesGoalIsTheMeanOfItsClustersGoals) {
  const Clusters clusters = build_clusters(random_cloud(), {8, 0.0, 500});
  const Eigen::VectorXd masses = Eigen::VectorXd::Ones(random_cloud().cols());
  ClusterMatcher matcher(random_cloud(), masses, clusters, ShapeMatchingParams{});
  std::mt19937 generator(1);
  std::normal_distribution<double> noise(0.0, 0.05);
  Eigen::Matrix3Xd current = random_cloud();
  for (Eigen::Index i = 0; i < current.cols(); ++i) {
    current.col(i) += Eigen::Vector3d(noise(generator), noise(generator), noise(generator));
  }
  Eigen::Matrix3Xd goals;
  matcher.match(current, goals);
  std::vector<Eigen::Vector3d> sums(static_cast<std::size_t>(current.cols()),
                                    Eigen::Vector3d::Zero());
  std::vector<int> counts(static_cast<std::size_t>(current.cols()), 0);
  for (int m = 0; m < matcher.num_memberships(); ++m) {
    const auto i = static_cast<std::size_t>(matcher.particle_of_membership(m));
    sums[i] += matcher.membership_goal(m);
    ++counts[i];
  }
  for (Eigen::Index i = 0; i < current.cols(); ++i) {
    const auto index = static_cast<std::size_t>(i);
    EXPECT_TRUE(goals.col(i).isApprox(sums[index] / counts[index], 1e-14)) << i;
  }
}

// The kernels take a cluster's members four and eight at a time, then the rest one by one: every
// size from one member to a few rounds past eight, in both bases, must give the same goals. A
// map of a cluster's own basis (linear: any 3x3 map, quadratic: any field of its nine
// monomials) is fitted exactly, so each goal is its member's deformed position to round-off.
TEST(ShapeMatchingClusters, EveryClusterSizeFitsAMapOfItsBasisExactly) {
  Eigen::Matrix<double, 3, 9> field;
  field << 1.1, 0.2, -0.1, 0.3, -0.2, 0.1, 0.4, 0.0, -0.3,  //
      -0.1, 0.9, 0.2, 0.0, 0.5, -0.4, 0.1, 0.2, 0.0,        //
      0.2, 0.1, 1.2, -0.3, 0.0, 0.2, 0.0, -0.1, 0.3;
  for (const auto type :
       {ShapeMatchingParams::Type::kLinear, ShapeMatchingParams::Type::kQuadratic}) {
    ShapeMatchingParams params;
    params.type = type;
    params.beta = 1.0;
    params.preserve_volume = false;
    params.rotation = ShapeMatchingParams::Rotation::kSvd;
    const int basis = type == ShapeMatchingParams::Type::kLinear ? 3 : 9;
    for (int n = 1; n <= 27; ++n) {
      const Eigen::Matrix3Xd rest = random_cloud().leftCols(n);
      Clusters one;
      one.seeds = {0};
      one.radius = std::numeric_limits<double>::infinity();
      one.offsets = {0, n};
      one.members.resize(static_cast<std::size_t>(n));
      std::iota(one.members.begin(), one.members.end(), 0);
      Eigen::VectorXd masses(n);
      for (int i = 0; i < n; ++i) {
        masses(i) = 1.0 + 0.1 * (i % 5);  // unequal: the weights enter every sum
      }
      ClusterMatcher matcher(rest, masses, one, params);
      Eigen::Matrix3Xd deformed(3, n);
      for (int i = 0; i < n; ++i) {
        const Eigen::Vector3d q = rest.col(i);
        Eigen::Matrix<double, 9, 1> monomials;
        monomials << q, q.cwiseAbs2(), q.x() * q.y(), q.y() * q.z(), q.z() * q.x();
        deformed.col(i) = field.leftCols(basis) * monomials.head(basis);
      }
      Eigen::Matrix3Xd goals;
      matcher.match(deformed, goals);
      for (int i = 0; i < n; ++i) {
        EXPECT_LT((goals.col(i) - deformed.col(i)).norm(), 1e-9)
            << "basis " << basis << ", " << n << " members, member " << i;
      }
    }
  }
}

}  // namespace
}  // namespace softbench::shape_matching
