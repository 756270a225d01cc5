// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace softbench::collision {

/// m: the farthest any vertex moved from `from` to `to` (3 x #V each, the same vertices),
/// relative to a common `shift`: max |to_v - from_v - shift|.
double largest_move(const Eigen::Matrix3Xd& from,
                    const Eigen::Matrix3Xd& to,
                    const Eigen::Vector3d& shift = Eigen::Vector3d::Zero());
/// m: the farthest any of a rigid body's `vertices` (its own frame) moves from pose `from` to
/// pose `to`, relative to `shift`; no point on the surface they span moves farther (a rigid
/// motion is affine).
double largest_move(const Eigen::Matrix3Xd& vertices,
                    const Eigen::Isometry3d& from,
                    const Eigen::Isometry3d& to,
                    const Eigen::Vector3d& shift = Eigen::Vector3d::Zero());

/// What is known, without a query, of how far each of a rigid instrument's sample points is
/// from a deforming closed surface (the tissue's) and on which side: conservative advancement.
/// A nearest-point query gives a sample's signed distance d; until the surface or the
/// instrument moves, |d| stays, and each move changes it by at most the largest move of a
/// surface point relative to the sample. Measured against any common shift u (the instrument's
/// origin's move), |dx - ds| <= |dx - u| + |ds - u|: at most the largest move of any surface
/// vertex less u (a surface point moves as a blend of its triangle's corners) plus the largest
/// of any instrument vertex less u (a rigid motion moves a point on the instrument's surface no
/// farther than its farthest-moving vertex). With u = 0 that is the sum of the two largest
/// moves; with the tool's own shift, tissue carried along by the tool (the probe pressing, the
/// grasp pulling) spends little of the bound. So |d| minus the moves summed since the query is
/// a lower bound, and while it is positive the sample has not crossed the surface: its side is
/// the query's. A sample far from the surface is queried again only once the summed moves could
/// have brought it near; on the liver pressed by the probe, most of the probe's points are
/// millimetres to centimetres off the surface and each step moves it by a fraction of one.
///
/// The side is the pseudonormal test's (MeshDistance). On a surface folded over itself that test
/// can change its answer far from the surface, where a fresh query would call a point inside a
/// fold; the bound keeps the side it had, which is what the contact's fold test decides for such
/// points anyway.
class SampleClearance {
 public:
  /// `samples` points on the instrument whose mesh has vertices `instrument` (its own frame).
  SampleClearance(Eigen::Index samples, const Eigen::Matrix3Xd& instrument);

  /// The state the next queries are made in: the surface's vertices `surface` (3 x #V, the same
  /// count every call) and the instrument at `pose`. Adds the largest moves since the last state.
  void advance(const Eigen::Matrix3Xd& surface, const Eigen::Isometry3d& pose);

  /// Whether sample i is known to be outside the surface by at least `distance`.
  bool outside_by(Eigen::Index i, double distance) const {
    return side_[static_cast<std::size_t>(i)] > 0 && bound(i) >= distance;
  }
  /// Whether sample i is known to be inside the surface by more than `depth`.
  bool inside_by(Eigen::Index i, double depth) const {
    return side_[static_cast<std::size_t>(i)] < 0 && bound(i) > depth;
  }
  /// Whether sample i is known to be farther than `distance` from the surface, on either side.
  bool far_by(Eigen::Index i, double distance) const { return bound(i) > distance; }
  /// A query's signed distance for sample i in the current state (negative inside), and the
  /// surface triangle nearest to it.
  void record(Eigen::Index i, double signed_distance, int triangle);
  /// The triangle sample i's last query found nearest (-1: none yet): where the next query of
  /// that sample starts (MeshDistance::nearest_within's hint), since samples move little from
  /// step to step.
  int hint(Eigen::Index i) const { return triangle_[static_cast<std::size_t>(i)]; }
  /// What a query bounded by `distance` (MeshDistance::nearest_within) found for sample i: no
  /// surface point nearer, side unknown (only far_by() can use it).
  void record_far(Eigen::Index i, double distance);

 private:
  double bound(Eigen::Index i) const {
    const auto k = static_cast<std::size_t>(i);
    return clearance_[k] - (travel_ - travel_at_[k]);
  }

  Eigen::Matrix3Xd instrument_;
  Eigen::Matrix3Xd surface_;  ///< the last state's surface
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  bool have_state_ = false;
  double travel_ = 0.0;            ///< m: the largest moves summed over every state change
  std::vector<double> clearance_;  ///< per sample: |d| at its last query
  std::vector<double> travel_at_;  ///< per sample: travel_ at its last query
  std::vector<signed char> side_;  ///< per sample: +1 outside, -1 inside, 0 unknown
  std::vector<int> triangle_;      ///< per sample: the nearest triangle its last query found
};

}  // namespace softbench::collision
