// SPDX-License-Identifier: MIT
// Contact between a deforming tissue surface and a rigid instrument, as data for the models:
// each step the tissue vertices the instrument must move, and where to. The thesis's criterion
// is that the instrument neither passes through the tissue nor floats away from it; two kinds of
// penetration break the first half, so both are resolved:
//   - a tissue vertex inside the instrument is projected to the instrument's surface (plus the
//     margin), found by the nearest point on the instrument mesh and an angle-weighted
//     pseudonormal inside test, in the instrument's own frame (its tree never changes);
//   - a point of the instrument inside the tissue (a thin tip between tissue vertices, the face
//     of a blunt tool) pushes the nearest tissue surface triangle inward along its normal until
//     the point is the margin outside; the push is spread over the triangle's vertices by their
//     barycentric weights (the least-norm vertex displacements that move that point of the
//     triangle by the push). The points are the instrument's vertices plus samples on its
//     faces no farther apart than half the tissue surface's mean edge, so that no tissue
//     triangle passes between them (collision/instrument_samples.h). A point "inside" by the
//     pseudonormal test but behind a fold of the tissue's surface (its push would be into the
//     instrument, or it is deeper than the step's motion can bring it) pushes nothing.
// A vertex that several contacts move keeps the largest move. Contact is judged on the tissue
// where it is and where it would be at the step's end without contact (x + dt v). Contacts hold
// while tissue and instrument are within twice the margin and the previous step's constraint
// force pressed the tissue away from the instrument (an active set); a pressed vertex the
// instrument withdraws from along the contact normal follows it while it presses (implicit
// models spring back within a step), and is let go, not pulled, once its force turns adhesive.
// The contact is frictionless: a tissue vertex's target is held along the contact normal only
// (VertexTarget::push; the vertex slides along the instrument), so the force on it, and on the
// tool, is the normal force. A corner of a triangle an instrument point pushes is held fully.
// Within the step, refine() settles that active set: after the body was stepped, a tissue
// vertex's hold whose force pulled is dropped, a vertex that ended inside the margin is held on
// it, and a triangle that ended around an instrument point is held outside it; the harness
// repeats the step from its start (SceneStepper::step).
// The thesis's measure of contact (table 4.2), the intersecting triangle pairs of the tissue's and
// the instrument's BVHs, is counted on request (count_triangle_pairs()): no hold uses it, so the
// harness counts it after each step, outside the step's timed work, as it measures penetration.
// The work follows the contact, not the tissue: while nothing is held and the instrument is out
// of the contact's reach of the tissue (where the step starts and in its free flight), a step
// costs a pass over the vertices and nothing is refitted or searched; near it, an instrument
// point is searched for only within that reach (farther points push nothing), and what earlier
// searches found spares most points a search (SampleClearance) and starts the others' searches
// at the triangle found last (MeshDistance::nearest_within's hint).
#pragma once

#include "collision/bvh.h"
#include "collision/bvh_collide.h"
#include "collision/mesh_distance.h"
#include "collision/query_stats.h"
#include "collision/sample_clearance.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>
#include <vector>

namespace softbench::collision {

/// A tissue vertex the contact moves: where it must be at the end of the step.
struct VertexTarget {
  int vertex = -1;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< m, world
  /// Unit direction in which the instrument pushes the vertex (away from the instrument); the
  /// constraint force on the vertex along it is the contact's normal force.
  Eigen::Vector3d push = Eigen::Vector3d::Zero();
  /// Whether the vertex may slide along the instrument (held along `push` only: frictionless).
  /// A tissue vertex's own contact slides; a corner of a triangle an instrument point pushes is
  /// held fully, so its triangle stays under the point within the step.
  bool slides = true;
};

/// What one detection found.
struct ContactReport {
  /// intersecting tissue-instrument triangle pairs (count_triangle_pairs())
  int triangle_pairs = 0;
  double max_penetration = 0.0;  ///< m: the deepest tissue vertex or instrument point (measure)
  /// Whether the step's trees were refitted and searched (resolve): not when nothing was held
  /// and the instrument was out of the contact's reach of the tissue, at the step's start and in
  /// its free flight.
  bool searched = false;
};

struct InstrumentContactOptions {
  double margin = 2e-4;  ///< m: the gap kept between tissue and instrument
  BvhSchedule tissue_schedule = BvhSchedule::liver();
  BvhSchedule instrument_schedule = BvhSchedule::instrument();
};

class InstrumentContact {
 public:
  /// `tissue_surface`: the tissue's closed outward boundary, as triangles over the tissue's
  /// vertex indices (3 x #T) with the tissue's rest positions (3 x #V). `instrument`: a closed
  /// outward mesh in its own frame. Throws InputError if either is not closed.
  InstrumentContact(const Eigen::Matrix3Xd& tissue_positions,
                    const Eigen::Matrix3Xi& tissue_surface,
                    const TriMesh& instrument,
                    InstrumentContactOptions options = {});

  /// The targets for a step of `dt` that ends with the instrument at `pose` (its frame ->
  /// world), from the tissue's positions and velocities at the step's start (contact is judged
  /// on the free-flight prediction x + dt v) and the constraint forces (3 x #V, N) the previous
  /// step's targets exerted (zero on the first step). Refits the tissue's trees where the
  /// instrument is within reach (report().searched).
  const std::vector<VertexTarget>& resolve(const Eigen::Isometry3d& pose,
                                           const Eigen::Matrix3Xd& positions,
                                           const Eigen::Matrix3Xd& velocities,
                                           double dt,
                                           const Eigen::Matrix3Xd& last_forces);

  /// The active set's correction within a step, after the body was stepped with resolve()'s
  /// targets (and earlier corrections) to `positions` with `forces` (3 x #V, N) on its
  /// constraints: a target whose force pulls the tissue toward the instrument is dropped (no
  /// contact is adhesive), a surface vertex that ended inside the margin around the instrument
  /// at `pose` gets a target on its surface plus the margin (a dropped one only if it ended
  /// inside the instrument itself), and a triangle that ended around a point of the instrument
  /// is held the margin outside it. Returns whether the targets changed (then the caller
  /// repeats the step from its start with them).
  bool refine(const Eigen::Isometry3d& pose,
              const Eigen::Matrix3Xd& positions,
              const Eigen::Matrix3Xd& forces);
  /// Whether refine() with these arguments would change the targets, leaving them as they are:
  /// for a step that ran out of passes, whether its holds had settled (a measure: the samples'
  /// clearances and the tissue's tree are left at `positions`, as measure() leaves them).
  bool refine_would_change(const Eigen::Isometry3d& pose,
                           const Eigen::Matrix3Xd& positions,
                           const Eigen::Matrix3Xd& forces);
  /// The current targets (resolve()'s, as refine() changed them).
  const std::vector<VertexTarget>& targets() const { return targets_; }

  /// The thesis's measure of contact (table 4.2): the intersecting triangle pairs of the tissue
  /// where the last resolve()'s step started and the instrument where it ends, as that step's
  /// detection saw them (0 where it did not search). A measure only, which the targets do not
  /// use: the harness takes it after the step, outside the step's timed work (with measure()),
  /// `positions` being the tissue's at the step's end, where the tissue's tree is left. Refits
  /// the instrument's tree, and the tissue's twice.
  int count_triangle_pairs(const Eigen::Matrix3Xd& positions);

  /// Penetration of the tissue at `positions` by the instrument at `pose`, without resolving
  /// (for metrics after a step): fills the returned report's vertex counts and
  /// max_penetration.
  ContactReport measure(const Eigen::Isometry3d& pose, const Eigen::Matrix3Xd& positions);

  /// m: signed distance of a world point from the instrument's surface at `pose` (negative
  /// inside).
  double instrument_distance(const Eigen::Isometry3d& pose, const Eigen::Vector3d& point) const;

  const ContactReport& report() const { return report_; }

 private:
  /// predicted_, start_ and tissue_motion_ for a step from `positions` with `velocities`;
  /// returns the box of the tissue where it starts and in its free flight.
  Aabb start_step(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities, double dt);
  void resolve_tissue_vertices(const Eigen::Isometry3d& pose, const Eigen::Matrix3Xd& positions);
  void resolve_instrument_vertices(const Eigen::Isometry3d& pose);
  void propose(int vertex, const Eigen::Vector3d& move, const Eigen::Vector3d& push, bool slides);
  bool was_pressed(int vertex) const;
  bool on_surface(const Eigen::Isometry3d& pose, const VertexTarget& target) const;
  bool hold_tissue_around_points(const Eigen::Isometry3d& pose, const Eigen::Matrix3Xd& positions);
  /// Whether instrument sample `sample` at `pose`, inside the tissue by `nearest`, is behind a
  /// fold of the tissue's surface instead (see the definition).
  bool behind_fold(Eigen::Index sample,
                   const Eigen::Isometry3d& pose,
                   const MeshDistance::Nearest& nearest) const;
  /// Per tissue vertex: 1 once refine() dropped its target this step (it is not taken again).
  std::vector<char> dropped_;
  /// Per tissue vertex: its target's index in targets_ while refine() runs, else -1.
  std::vector<int> target_index_;
  std::vector<int> dropped_vertices_;  ///< where dropped_ is set, to clear it at the next step
  /// refine_would_change()'s copy of the targets to put back (kept: no allocation each time).
  std::vector<VertexTarget> saved_targets_;
  /// m: how far from the tissue's surface an instrument point can still push it or be checked
  /// for a fold, this step (see the definition).
  double cull_radius() const;
  /// The tissue's surface point nearest to instrument sample i at `point` (world) within
  /// `radius`, searched from the triangle the sample's last search found; what it found (or
  /// that nothing is that near) is recorded in clearance_.
  std::optional<MeshDistance::Nearest> search_sample(Eigen::Index i,
                                                     const Eigen::Vector3d& point,
                                                     double radius);
  bool follows_withdrawal(int vertex,
                          const Eigen::Vector3d& local_point,
                          const Eigen::Isometry3d& pose) const;

  InstrumentContactOptions options_;
  Eigen::Matrix3Xi tissue_surface_;
  std::vector<int> surface_vertices_;
  MeshDistance instrument_distance_;  ///< in the instrument's own frame: never refitted
  MeshDistance tissue_distance_;      ///< the tissue at the step's start
  MeshDistance predicted_distance_;   ///< the tissue's free flight to the step's end
  Bvh instrument_tree_;               ///< world frame, for the triangle-pair query
  Eigen::Matrix3Xi instrument_triangles_;
  Eigen::Matrix3Xd instrument_local_;
  Eigen::Matrix3Xd instrument_world_;
  double spacing_;                  ///< m: half the tissue surface's mean edge at rest
  Eigen::Matrix3Xd samples_local_;  ///< points on the instrument's surface (vertices and more)
  Eigen::Matrix3Xd sample_normals_local_;  ///< the instrument's outward pseudonormal at each sample
  Aabb instrument_box_;                    ///< the instrument's world box at this step's pose
  SampleClearance clearance_;   ///< what is known of each sample's distance without a query
  double tissue_motion_ = 0.0;  ///< m: this step's largest free-flight move of a tissue vertex
  double tool_motion_ = 0.0;    ///< m: this step's largest move of an instrument vertex
  Eigen::Matrix3Xd predicted_;  ///< the tissue at the step's end without contact
  CollideBuffers buffers_;
  std::vector<TrianglePair> pairs_;

  std::vector<int> pressed_;                ///< per tissue vertex: 1 if pushed away last step
  std::vector<Eigen::Vector3d> last_push_;  ///< per tissue vertex: its push last step
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d start_pose_ = Eigen::Isometry3d::Identity();  ///< the pose a step starts at
  Eigen::Matrix3Xd start_;             ///< the tissue at the step's start
  std::vector<char> has_move_;         ///< per tissue vertex: a move was proposed this step
  std::vector<Eigen::Vector3d> move_;  ///< per tissue vertex: this step's largest move
  std::vector<Eigen::Vector3d> push_;
  std::vector<char> slides_;  ///< per tissue vertex: this step's largest move may slide
  std::vector<int> moved_;    ///< vertices with a move this step
  std::vector<VertexTarget> targets_;
  ContactReport report_;
};

}  // namespace softbench::collision
