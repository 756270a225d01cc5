// SPDX-License-Identifier: MIT
#pragma once

#include "models/shape_matching/clusters.h"
#include "models/shape_matching/shape_matching.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <vector>

namespace softbench::shape_matching {

/// The matching half of shape matching (shape_matching.h): per cluster, the goal positions of
/// its particles for their current positions, and per particle the mean of its clusters' goals.
/// Works on any point set (no mesh), so the Figure 3.10 benchmark uses it on random points.
///
/// Construction precomputes everything that depends on the rest shape: per membership the
/// particle index, m_i / M and the scaled, centred basis q (3) or q~ (9); per cluster Aqq^-1
/// (pseudo-inverse) and the scale. match_cluster() allocates nothing.
///
/// Layout: memberships are numbered cluster by cluster (cluster k owns [offset_k, offset_k +
/// n_k)); each cluster's basis is a D x n_k row-major block (D = 3 or 9) and its work space a
/// 3 x n_k one, so every per-membership loop runs over contiguous rows and vectorises.
class ClusterMatcher {
 public:
  /// `rest` 3 x #P (m), `masses` #P (> 0). Every particle must be in at least one cluster
  /// (build_clusters() guarantees it). Only type, beta, rotation and rotation_iterations of
  /// `params` are used.
  ClusterMatcher(const Eigen::Matrix3Xd& rest,
                 const Eigen::VectorXd& masses,
                 const Clusters& clusters,
                 const ShapeMatchingParams& params);

  int num_particles() const { return static_cast<int>(particle_offsets_.size()) - 1; }
  int num_clusters() const { return static_cast<int>(cluster_offsets_.size()) - 1; }
  int num_memberships() const { return static_cast<int>(member_particle_.size()); }
  int basis_size() const { return dim_; }  ///< 3 (linear) or 9 (quadratic)
  /// The memberships of cluster k: offsets into the membership arrays.
  int cluster_begin(int cluster) const { return cluster_offsets_[index(cluster)]; }
  int cluster_end(int cluster) const { return cluster_offsets_[index(cluster) + 1]; }
  int cluster_of_membership(int membership) const;
  int particle_of_membership(int membership) const { return member_particle_[index(membership)]; }

  /// Matches cluster k to `positions` (3 x #P): its rotation (warm-started from its last one),
  /// its map T, and the goal of each of its members, kept per membership. Returns the rotation
  /// iterations taken (0 for the SVD). Clusters are independent: any thread may match any
  /// cluster, each once per step.
  int match_cluster(int cluster, const Eigen::Matrix3Xd& positions);

  /// Particle i's goal: the mean of its clusters' goals, summed in increasing cluster order (the
  /// same result on any number of threads). Valid after every cluster was matched.
  Eigen::Vector3d goal(int particle) const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int s = particle_offsets_[index(particle)]; s < particle_offsets_[index(particle) + 1];
         ++s) {
      const double* slot = work_.data() + slot_start_[index(s)];
      const std::ptrdiff_t stride = slot_stride_[index(s)];
      sum += Eigen::Vector3d(slot[0], slot[stride], slot[2 * stride]);
    }
    return sum * inverse_count_(particle);
  }
  /// The goal of one membership (cluster's goal for its particle), after its cluster was matched.
  Eigen::Vector3d membership_goal(int membership) const;

  /// Both loops, OpenMP over clusters and particles when it pays: `goals` (3 x #P, resized once)
  /// receives every particle's goal. Returns the largest rotation iterations of any cluster.
  int match(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd& goals);

  /// The rotation cluster k found in its last match (I before any).
  Eigen::Matrix3d rotation(int cluster) const {
    return rotations_[index(cluster)].toRotationMatrix();
  }
  /// Forgets the state carried between matches: every rotation back to I, every reference
  /// point back to the rest centre of mass (so a run after reset() repeats bit for bit).
  void reset();
  std::size_t memory_bytes() const;

 private:
  static std::size_t index(int i) { return static_cast<std::size_t>(i); }
  template <int D>
  int match_cluster_with(int cluster, const Eigen::Matrix3Xd& positions);
  template <int D>
  void precompute(const Eigen::Matrix3Xd& rest,
                  const Eigen::VectorXd& masses,
                  const Clusters& clusters);

  ShapeMatchingParams params_;
  int dim_ = 0;

  // Per membership, cluster by cluster.
  std::vector<int> member_particle_;
  std::vector<double> member_weight_;  ///< m_i / M of the cluster
  std::vector<double> basis_;          ///< per cluster a D x n_k row-major block
  std::vector<double> work_;           ///< per cluster a 3 x n_k block: m p / M, then goals

  // Per cluster.
  std::vector<int> cluster_offsets_;           ///< #clusters + 1
  std::vector<double> scale_;                  ///< m, RMS radius of the rest cluster
  std::vector<double> moment_inverse_;         ///< D x D per cluster: Aqq^-1 (pseudo-inverse)
  std::vector<Eigen::Quaterniond> rotations_;  ///< warm starts
  std::vector<double> rest_centres_;           ///< 3 per cluster, m: c0
  std::vector<double> reference_;  ///< 3 per cluster, m: c of the last match (c0 at first)

  // Per particle: its memberships (compressed rows), as where their goals sit in work_.
  std::vector<int> particle_offsets_;        ///< #P + 1
  std::vector<std::ptrdiff_t> slot_start_;   ///< index of the goal's x in work_
  std::vector<std::ptrdiff_t> slot_stride_;  ///< distance to its y (and from y to z)
  Eigen::VectorXd inverse_count_;            ///< 1 / number of clusters holding the particle
};

}  // namespace softbench::shape_matching
