// SPDX-License-Identifier: MIT
#pragma once

#include "models/double_lanes.h"
#include "models/shape_matching/clusters.h"
#include "models/shape_matching/shape_matching.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstddef>
#include <span>
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
/// Held particles (hold()) are kinematic: infinite mass in every cluster they belong to, in the
/// limit rather than with a large weight. Per cluster with held members H:
/// - the rigid placement is theirs: the centre is their centre of mass c_H, and the rotation
///   maximises tr(R^T A_H) first and tr(R^T A_F) among those maximisers (A_H, A_F the held and
///   free members' moments about c_H): with one held particle (or several at one point) it is
///   the free members' rotation about it; with held particles on a line, a hinge: R maps the
///   rest line onto the current one and the free members choose the angle about it, in closed
///   form; otherwise the held particles' own rotation (the warm-started iteration, or the SVD
///   where it would converge slowly on such an anisotropic moment);
/// - the deformable fit (A, A~) is that placement plus the free fit's deviation from it,
///   projected to vanish at the held members: with T_0 the ordinary fit ([c - r, Apq Aqq^-1]
///   on [1 b], r the reference point) and Rig the placement, T = Rig + (T_0 - Rig) P, where P
///   ((D + 1) x (D + 1)) depends on the rest shape and H only: I minus the projector onto the
///   held members' span orthogonal in the ordinary fit's metric (Aqq^-1), so the deviation's
///   weighted size never exceeds the free fit's. (Requiring the fit to pass through the held
///   particles' positions instead, the infinite-mass limit of the ordinary fit, is the same
///   when they moved rigidly, but held particles moved apart from one another, as a contact
///   spreading a push over a triangle's corners does, then demand a cluster-wide stretch that
///   throws the far goals off by orders of magnitude.) The held members' span is pseudo-
///   inverted relative to its own largest eigenvalue, so a few held particles never fall under
///   Aqq's cutoff and no huge weight makes the 9 x 9 moment ill-conditioned;
/// - the goals are g_i = c_H + T (b_i - b_H), b_H the held members' mean basis.
/// So a held particle's goal in each of its clusters is its place in the held set's rigid
/// placement: the particle itself whenever the held set moved rigidly from rest (one held
/// particle always), to round-off. Only clusters with held members carry the extra data, and
/// hold() updates only the clusters whose held set changed since its last call.
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
  /// Whether a step's work (a fit per membership, a pull per particle, per pass) is worth a
  /// parallel region. Measured on the thesis's liver (1215 particles, 50 clusters, about 4,800
  /// memberships, four passes): two threads save at most 10% on a quiet machine (288 -> 262 us)
  /// and cost 3-70x when the other core is busy (a thread descheduled at one of a step's ten
  /// barriers holds up the rest: 0.2-14 ms a step). So it runs on one thread up to several
  /// times the liver's work, and a tiny body (a test bar of 90 particles in 50 clusters has
  /// 4,500 memberships) never pays for a thread team.
  bool worth_parallel() const { return num_memberships() + num_particles() >= kParallelWork; }
  static constexpr int kParallelWork = 40000;
  /// Particles per block of a per-particle loop: a few microseconds of work each, the unit a
  /// thread takes.
  static constexpr int kParticleChunk = 256;
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
    // Four lanes a goal (its three coordinates and the next one's x, which the padding keeps in
    // range): one load and one add a membership, each lane summed in the same order.
    Quad sum = {0.0, 0.0, 0.0, 0.0};
    for (int s = particle_offsets_[index(particle)]; s < particle_offsets_[index(particle) + 1];
         ++s) {
      sum += load_quad(goals_.data() + 3 * static_cast<std::ptrdiff_t>(slot_membership_[index(s)]));
    }
    return Eigen::Vector3d(sum[0], sum[1], sum[2]) * inverse_count_(particle);
  }
  /// The goal of one membership (cluster's goal for its particle), after its cluster was matched.
  Eigen::Vector3d membership_goal(int membership) const;

  /// Both loops, OpenMP over clusters and particles when it pays: `goals` (3 x #P, resized once)
  /// receives every particle's goal. Returns the largest rotation iterations of any cluster.
  int match(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd& goals);

  /// Makes exactly `particles` (indices in range, each once) the held ones from the next match
  /// on: hold_changes() then refit_held() for each changed cluster, on this thread.
  void hold(std::span<const int> particles);
  /// The first half of hold(): compares `particles` with the held set of the last call, and
  /// lists the clusters whose held set changed (a cluster no longer holding any particle drops
  /// its data here). Returns how many: refit_held(0 .. count - 1) must run before the next
  /// match. Serial; allocates only when a cluster gets held members for the first time.
  int hold_changes(std::span<const int> particles);
  /// Recomputes the held data of the index-th changed cluster of the last hold_changes(). The
  /// changed clusters are independent: any thread may refit any of them.
  void refit_held(int index);
  /// How many clusters the last hold_changes() listed for refitting.
  int num_refits() const { return static_cast<int>(changed_clusters_.size()); }
  bool is_held(int particle) const { return held_flags_[index(particle)] != 0; }
  /// Clusters that have held members.
  int num_held_clusters() const {
    return num_clusters() - static_cast<int>(std::count(held_slot_.begin(), held_slot_.end(), -1));
  }
  /// For a held particle after a match: the pull (m, like g - x) its clusters' free members
  /// take from it, per unit of its mass and alpha / dt^2. A cluster with held members moves
  /// its goals toward the held ones: its members' pulls (particle i: m_i / n_i (g_i - x_i), n_i
  /// its cluster count) no longer sum to zero, and the held members must supply the balance. It
  /// is shared as the multipliers of the affine fit would: the shares reproduce the pulls' net
  /// force and first moment (so two held ends of a stretched cluster feel its tension), each
  /// held particle taking m_h (a + B (q_h - q_H)).
  Eigen::Vector3d held_pull(int particle) const;

  /// The rotation cluster k found in its last match (I before any).
  Eigen::Matrix3d rotation(int cluster) const {
    return rotations_[index(cluster)].toRotationMatrix();
  }
  /// Forgets the state carried between matches: every rotation back to I, every reference
  /// point back to the rest centre of mass, and the held set (none held; the data of held
  /// clusters is kept for reuse), so a run after reset() repeats bit for bit.
  void reset();
  std::size_t memory_bytes() const;

 private:
  /// The largest basis with its constant: 1 + 9.
  static constexpr int kMaxFit = 10;
  /// What a cluster with held members keeps (see the class comment). Sized for the quadratic
  /// basis; linear mode uses the top-left blocks.
  struct HeldCluster {
    std::vector<int> members;  ///< positions in the cluster of its held members, increasing
    double weight = 0.0;       ///< sum of their m / M
    /// 0: all at one point; 1: on a line; 2: on a plane; 3: spanning space (the rank of their
    /// linear rest moment, with a margin: see kHeldLineCutoff).
    int rank = 0;
    Eigen::Matrix<double, 9, 1> mean = Eigen::Matrix<double, 9, 1>::Zero();  ///< b_H
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  ///< rank 1: the line's rest direction
    Eigen::Matrix3d spread_inverse = Eigen::Matrix3d::Zero();  ///< (sum m/M (q-q_H)(.)^T)^+
    Eigen::Matrix3d span = Eigen::Matrix3d::Zero();            ///< projector onto what they span
    /// Columns 1..D of P ((D + 1) x D; see the class comment).
    Eigen::Matrix<double, kMaxFit, 9> keep = Eigen::Matrix<double, kMaxFit, 9>::Zero();
    bool refitted = false;  ///< refitted since its last match
    // The pulls' sums over the rest shape (refit_held_with()), so that a match reads the
    // members' positions once, in the moments' pass: with s_j = m_j / (M n_j) (n_j the
    // particle's cluster count) and u_j = q_j - q_H, the shares' total sum s_j, sum s_j u_j,
    // sum s_j b_j and sum s_j b_j u_j^T.
    double share_total = 0.0;
    Eigen::Vector3d share_offset = Eigen::Vector3d::Zero();
    Eigen::Matrix<double, 9, 1> share_basis = Eigen::Matrix<double, 9, 1>::Zero();
    Eigen::Matrix<double, 9, 3> share_moment = Eigen::Matrix<double, 9, 3>::Zero();
    // Written by each match: the pull shares (held_pull()).
    Eigen::Vector3d pull = Eigen::Vector3d::Zero();         ///< a
    Eigen::Matrix3d pull_moment = Eigen::Matrix3d::Zero();  ///< B
  };

  static std::size_t index(int i) { return static_cast<std::size_t>(i); }
  /// Cluster k's slices of the per-membership arrays (the layout above): the first membership,
  /// the member count, and where its particles, weights, basis rows (D x n) and work rows
  /// (3 x n) start.
  struct Slices {
    int begin;
    int n;
    const int* particle;
    const double* weight;
    const double* basis;
    double* work;
  };
  Slices slices(int cluster);
  template <int D>
  int match_cluster_with(int cluster, const Eigen::Matrix3Xd& positions);
  template <int D>
  int match_held(int cluster,
                 HeldCluster& held,
                 const Eigen::Matrix<double, 3, D>& apq,
                 const Eigen::Vector3d& reference,
                 const Eigen::Vector3d& centre);
  template <int D>
  void refit_held_with(int cluster, HeldCluster& held);
  std::size_t held_bytes() const;
  template <int D>
  void precompute(const Eigen::Matrix3Xd& rest,
                  const Eigen::VectorXd& masses,
                  const Clusters& clusters);

  ShapeMatchingParams params_;
  int dim_ = 0;

  // Per membership, cluster by cluster.
  std::vector<int> member_particle_;
  std::vector<double> member_weight_;  ///< m_i / M of the cluster
  /// 1 / the number of clusters holding the member's particle: the pulls' share of it
  std::vector<double> member_inverse_count_;
  std::vector<double> basis_;  ///< per cluster a D x n_k row-major block
  std::vector<double> work_;   ///< per cluster a 3 x n_k block: m (x - r) / M
  /// Per membership its goal (x, y, z side by side, for the per-particle gathers), and one more
  /// value so that four lanes can be read at the last.
  std::vector<double> goals_;

  // Per cluster.
  std::vector<int> cluster_offsets_;           ///< #clusters + 1
  std::vector<double> scale_;                  ///< m, RMS radius of the rest cluster
  std::vector<double> moment_inverse_;         ///< D x D per cluster: Aqq^-1 (pseudo-inverse)
  std::vector<Eigen::Quaterniond> rotations_;  ///< warm starts
  std::vector<double> rest_centres_;           ///< 3 per cluster, m: c0
  std::vector<double> reference_;      ///< 3 per cluster, m: c of the last match (c0 at first)
  std::vector<int> match_iterations_;  ///< match()'s rotation iterations per cluster

  // Per particle: its memberships (compressed rows), in increasing cluster order.
  std::vector<int> particle_offsets_;  ///< #P + 1
  std::vector<int> slot_membership_;   ///< the membership
  std::vector<int> slot_cluster_;      ///< the membership's cluster
  Eigen::VectorXd inverse_count_;      ///< 1 / number of clusters holding the particle

  // Held particles.
  std::vector<unsigned char> held_flags_;     ///< per particle: 1 if held (the last hold())
  std::vector<int> held_particles_;           ///< the particles of the last hold()
  std::vector<int> held_slot_;                ///< per cluster: its HeldCluster in held_pool_, or -1
  std::vector<HeldCluster> held_pool_;        ///< grows to the most clusters ever held at once
  std::vector<int> free_held_slots_;          ///< pool entries no cluster uses
  std::vector<unsigned char> changed_flags_;  ///< per cluster, during hold_changes()
  std::vector<int> changed_clusters_;         ///< the last hold_changes()'s, to refit
};

}  // namespace softbench::shape_matching
