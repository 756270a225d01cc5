// SPDX-License-Identifier: MIT
#include "models/shape_matching/clusters.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>

namespace softbench::shape_matching {
namespace {

/// The index of the largest value; the lowest such index on ties.
int index_of_largest(const Eigen::VectorXd& values) {
  int best = 0;
  for (int i = 1; i < values.size(); ++i) {
    if (values(i) > values(best)) {
      best = i;
    }
  }
  return best;
}

/// Squared distances from `points`' column `seed` to every point.
Eigen::VectorXd squared_distances_from(const Eigen::Matrix3Xd& points, int seed) {
  return (points.colwise() - points.col(seed)).colwise().squaredNorm().transpose();
}

/// The squared radius that gives `memberships` (seed, particle) pairs in all: the
/// memberships-th smallest squared seed-particle distance.
double squared_radius_for(const std::vector<Eigen::VectorXd>& distances, std::size_t memberships) {
  std::vector<double> all;
  all.reserve(distances.size() * static_cast<std::size_t>(distances.front().size()));
  for (const Eigen::VectorXd& row : distances) {
    all.insert(all.end(), row.data(), row.data() + row.size());
  }
  memberships = std::clamp<std::size_t>(memberships, 1, all.size());
  const auto nth = all.begin() + static_cast<std::ptrdiff_t>(memberships - 1);
  std::nth_element(all.begin(), nth, all.end());
  return *nth;
}

}  // namespace

std::vector<int> farthest_point_seeds(const Eigen::Matrix3Xd& points, int count) {
  assert(points.cols() > 0);
  const int num_points = static_cast<int>(points.cols());
  count = std::clamp(count, 1, num_points);
  const Eigen::Vector3d centroid = points.rowwise().mean();
  std::vector<int> seeds;
  seeds.reserve(static_cast<std::size_t>(count));
  seeds.push_back(
      index_of_largest((points.colwise() - centroid).colwise().squaredNorm().transpose()));
  // Each point's squared distance to the nearest seed so far.
  Eigen::VectorXd nearest = squared_distances_from(points, seeds.back());
  while (static_cast<int>(seeds.size()) < count) {
    seeds.push_back(index_of_largest(nearest));
    nearest = nearest.cwiseMin(squared_distances_from(points, seeds.back()));
  }
  return seeds;
}

Clusters build_clusters(const Eigen::Matrix3Xd& points, const ClusterSpec& spec) {
  assert(points.cols() > 0);
  const int num_points = static_cast<int>(points.cols());
  Clusters clusters;
  clusters.seeds = farthest_point_seeds(points, spec.count);
  const int count = clusters.count();
  if (count == 1) {
    clusters.radius = std::numeric_limits<double>::infinity();
    clusters.offsets = {0, num_points};
    clusters.members.resize(static_cast<std::size_t>(num_points));
    for (int i = 0; i < num_points; ++i) {
      clusters.members[static_cast<std::size_t>(i)] = i;
    }
    return clusters;
  }

  std::vector<Eigen::VectorXd> distances;  // squared, per seed
  distances.reserve(static_cast<std::size_t>(count));
  for (const int seed : clusters.seeds) {
    distances.push_back(squared_distances_from(points, seed));
  }
  const double squared_radius =
      spec.radius > 0.0
          ? spec.radius * spec.radius
          : squared_radius_for(
              distances, static_cast<std::size_t>(count)
                             * static_cast<std::size_t>(std::max(spec.particles_per_cluster, 1)));
  clusters.radius = std::sqrt(squared_radius);

  // The seed nearest to each particle (lowest index on ties), for particles in no region.
  std::vector<int> nearest_seed(static_cast<std::size_t>(num_points), 0);
  for (int i = 0; i < num_points; ++i) {
    for (int k = 1; k < count; ++k) {
      if (distances[static_cast<std::size_t>(k)](i)
          < distances[static_cast<std::size_t>(nearest_seed[static_cast<std::size_t>(i)])](i)) {
        nearest_seed[static_cast<std::size_t>(i)] = k;
      }
    }
  }
  std::vector<bool> covered(static_cast<std::size_t>(num_points), false);
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < num_points; ++i) {
      if (distances[static_cast<std::size_t>(k)](i) <= squared_radius) {
        covered[static_cast<std::size_t>(i)] = true;
      }
    }
  }

  clusters.offsets.reserve(static_cast<std::size_t>(count) + 1);
  clusters.offsets.push_back(0);
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < num_points; ++i) {
      const bool inside = distances[static_cast<std::size_t>(k)](i) <= squared_radius;
      const bool adopted =
          !covered[static_cast<std::size_t>(i)] && nearest_seed[static_cast<std::size_t>(i)] == k;
      if (inside || adopted) {
        clusters.members.push_back(i);
      }
    }
    clusters.offsets.push_back(static_cast<int>(clusters.members.size()));
  }
  return clusters;
}

}  // namespace softbench::shape_matching
