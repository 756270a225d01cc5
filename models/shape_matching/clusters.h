// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <span>
#include <vector>

namespace softbench::shape_matching {

/// What build_clusters() is asked for.
struct ClusterSpec {
  int count = 1;                   ///< clusters wanted; clamped to [1, #particles]
  double radius = 0.0;             ///< m, region radius; 0 = choose from particles_per_cluster
  int particles_per_cluster = 96;  ///< the target average size when radius is 0
};

/// Overlapping clusters of particles, as compressed rows: cluster k holds
/// members[offsets[k] .. offsets[k + 1]), in increasing particle order.
struct Clusters {
  std::vector<int> seeds;    ///< #clusters: the particle each cluster is centred on
  double radius = 0.0;       ///< m, the region radius used (+inf for one global cluster)
  std::vector<int> offsets;  ///< #clusters + 1
  std::vector<int> members;  ///< particle indices; sum of the cluster sizes

  int count() const { return static_cast<int>(seeds.size()); }
  std::span<const int> members_of(int cluster) const {
    return {members.data() + offsets[static_cast<std::size_t>(cluster)],
            members.data() + offsets[static_cast<std::size_t>(cluster) + 1]};
  }
};

/// `count` particles of `points` (3 x #P) spread by farthest-point sampling: the first is the
/// point farthest from the centroid, each next one the point farthest from those chosen (ties:
/// the lowest index). Deterministic. `count` is clamped to [1, #P]; #P must be > 0.
std::vector<int> farthest_point_seeds(const Eigen::Matrix3Xd& points, int count);

/// Clusters by region radius around farthest-point seeds (the thesis's "region radius"): cluster
/// k is every particle within `radius` of seed k. With spec.radius 0 the radius is the smallest
/// one that gives count * particles_per_cluster memberships in all (so clusters average about
/// particles_per_cluster particles). A particle within no region joins the cluster of its nearest
/// seed: every particle is in at least one cluster. count 1 gives one cluster of all particles.
/// O(count * #P log #P); deterministic.
Clusters build_clusters(const Eigen::Matrix3Xd& points, const ClusterSpec& spec);

}  // namespace softbench::shape_matching
