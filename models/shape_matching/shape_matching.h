// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/calibration_record.h"
#include "models/material.h"
#include "models/model_registry.h"
#include "models/soft_body.h"

#include <memory>
#include <optional>

namespace softbench {

// Meshless deformation by shape matching (Mueller, Heidelberger, Teschner & Gross 2005,
// "Meshless deformations based on shape matching"), as the thesis uses it (sections 3.4.4-3.4.5):
// the particles are the mesh vertices with lumped masses from the material density. The mesh's
// tets are used for nothing else, and the material's Young's modulus and Poisson's ratio are
// ignored: the stiffness is `alpha` (and the time step), not a material constant.
//
// Per cluster of particles with rest positions x0_i and masses m_i, and per step:
//   c = sum m_i x_i / M,  p_i = x_i - c,  q_i = x0_i - c0 (c0 the rest centre of mass);
//   Apq = sum m_i p_i q_i^T; R = the rotation of the polar decomposition Apq = R S;
//   linear:    A = Apq Aqq^-1, Aqq = sum m_i q_i q_i^T; A / cbrt(det A) keeps the volume;
//              T = beta A + (1 - beta) R, goal g_i = T q_i + c;
//   quadratic: q~ = [qx qy qz qx^2 qy^2 qz^2 qx qy qy qz qz qx] (9), A~ = Apq~ Aqq~^-1 (3 x 9),
//              T = beta A~ + (1 - beta) [R 0 0], g_i = T q~_i + c.
// A particle's goal is the average of its clusters' goals. The step (Mueller 2005, eq. 2 with
// predicted positions, as in position-based dynamics):
//   v* = v + dt f / m,  x* = x + dt v*,  goals g from x*,
//   v' = v* + alpha (g - x*) / dt,  x' = x* + alpha (g - x*)  (= x + dt v').
// For 0 < alpha <= 1 the pull never overshoots its goal: the step is stable at any dt.
//
// Departures from the paper, each needed for a property the tests check:
// - The quadratic terms of q~ are centred on their cluster's mass-weighted mean (the paper's q~
//   is not), so the fit has an intercept: a prescribed quadratic deformation is reproduced
//   exactly, and the goals keep the cluster's centre of mass (with one cluster the pull
//   conserves linear momentum).
// - q is scaled by the cluster's RMS radius before the fit, and Aqq^-1 is a pseudo-inverse
//   (eigenvalues below 1e-9 of the largest dropped): flat or tiny clusters stay finite.
// - With preserve_volume (the default) the linear part A is divided by cbrt(det A) in quadratic
//   mode as in linear mode (the paper keeps the volume of linear goals only), and only while
//   det A > 0.05; a cluster squashed or inverted beyond that follows R alone until it has
//   recovered (det A -> 0 would blow A up).
//
// Constraints: an exactly constrained particle is put on its target before the matching (with
// v = (target - x) / dt), and is not pulled toward its goal. Held fully by a hold that anchors
// the body (PositionConstraint::anchors: pinned, grasped), it is kinematic in every cluster it
// belongs to:
// infinite mass in the fit, in the limit (cluster_matching.h). The held particles of a cluster
// give it its centre and, as far as they span it, its rotation; the fitted deformation is the
// rest of the cluster's, relative to that placement and vanishing at them. So they anchor their
// clusters: a cluster's goal for a held particle is the particle itself whenever the held set
// moved rigidly (one held particle always). A contact's full hold (the corners of a triangle
// kept under a tool's point) does not anchor: held on its target all the same, it takes part in
// the fits with its own mass; as anchors, a few corners near a probe's tip set the rotations of
// whole clusters, and the four passes a step carried that error through the body (the thesis's
// liver under the probe: 178% volume change and 2,061 tets inverted as anchors, 8.9% and none
// stuck but one without). Held along a normal only (a frictionless contact or
// support, slid onto its plane), it keeps its mass in the fit: infinite mass would pin its
// clusters along the plane too, and the hold denies it only the normal part of its pull. The
// reaction on a fully held particle includes its share of what its clusters' pulls toward their
// anchored goals give their members, split among a cluster's held particles so that the shares
// match the pulls' net force and first moment. Only clusters with held members carry the
// extra data, updated only where the held set changed since the last step. A penalty
// constraint is a spring k (target - x) integrated implicitly on its own particle, so it is
// stable at any dt too.
//
// Passes (`iterations`): the match and the pull are repeated, each pass from where the last
// left the particles, and the velocity is the step's whole displacement over dt (one pass is
// the paper's step). Position-based engines iterate their constraints the same way; here the
// reason is the clusters' coupling: pinned particles anchor only the clusters they belong to,
// the others hang from those through the particles they share, whose goals are averages, so a
// body's weight crosses one cluster overlap per pass. A bar of ten clusters hanging from its
// top stretches to 7.2x its length with one pass, 2.6x with four, 1.8x with eight (the
// stretch beyond the length halves with each doubling). The liver of scenes/liver_gravity.json
// (7% of its vertices fixed, 15 of its 50 clusters holding some of them), with the thesis's
// alpha and beta at dt = 1/60 s, gains up to 144% of its volume with one pass and no volume
// kept, 59% with one pass and the volume kept, 8.9% with four passes (the default); it is then
// back within 1% of its shape 1.3 s after gravity is off. Four passes cost about four single-
// pass steps.
//
// Behaviour worth knowing: there is no damping parameter and no plasticity; the pull itself
// dissipates (with one cluster and one pass a deformation decays by sqrt(1 - alpha (1 -
// beta)) per step: 0.857 with the thesis's values). The stiffness is per step, not physical:
// halving dt doubles the pulls per second, and so do twice the passes. Nor is it one
// stiffness: against a reference liver, a shape-matched one that sags as much resists a probe
// several times harder (its press force comes from the few clusters under the probe, its sag
// from the chain of clusters to the anchors), so no alpha and beta match both (compare's table
// B reports what is left). With four passes the thesis's liver hangs about 2 cm lower on
// average, where the reference's hangs 6 cm lower.
//
// StepStats: `iterations` is the largest number of rotation iterations a cluster took in any
// pass (quaternion extraction; 0 for the SVD; a cluster whose held particles span a plane takes
// up to 4, whatever rotation_iterations says, before the SVD takes over); `residual` is the RMS
// of |g_i - x_i| over the particles not constrained exactly, before the last pass's pull,
// divided by the rest bounding-box diagonal (how far the body still was from its goals). elastic_energy() is NaN:
// shape matching has no energy.
// constraint_forces() is m (v' - v) / dt - f_ext at exactly constrained particles (f_ext:
// gravity and external forces) minus the internal forces on them (the pulls the hold denies
// them and, held fully, their share of their clusters' pulls, summed over the passes), and the
// spring force at
// penalty-constrained ones.

struct ShapeMatchingParams {
  enum class Type { kLinear, kQuadratic };
  enum class Rotation { kSvd, kQuaternion };

  /// "linear": goals from a 3x3 map (shear and stretch); "quadratic": from a 3x9 map (also
  /// twist and bend: the thesis's choice). Quadratic costs about twice as much per particle.
  Type type = Type::kQuadratic;
  /// Number of overlapping clusters (the thesis: 50), clamped to the number of particles. 1 = one
  /// global cluster holding every particle. More clusters: more local, larger deformation; one
  /// polar decomposition each, and more particle memberships to match.
  int clusters = 50;
  /// m, the region radius: a cluster is every particle within it of the cluster's seed. 0 =
  /// choose it so that on average about `particles_per_cluster` particles take part per cluster.
  /// Particles outside every region join their nearest seed's cluster, so none is left out.
  double cluster_radius = 0.0;
  /// Target average particles per cluster when cluster_radius is 0 (the thesis: 96). More:
  /// stiffer, smoother clusters and more overlap; the cost grows in proportion.
  int particles_per_cluster = 96;
  /// Fraction of the way to its goal a particle is pulled per step, in (0, 1] (the thesis:
  /// 0.72). 1: the shape is restored in one step (rigid); smaller: softer, more oscillation. The
  /// stiffness also depends on dt: the pull is per step.
  double alpha = 0.72;
  /// Blend in [0, 1] of the best linear (quadratic) map with the rotation (the thesis: 0.63).
  /// 0: rigid goals; larger: the cluster keeps more of its deformation (softer to shear, bend,
  /// twist), and recovers more slowly.
  double beta = 0.63;
  /// "svd": the polar rotation from a 3x3 SVD, exact, ~0.6 us per cluster; "quaternion": Mueller,
  /// Bender, Chentanez & Macklin 2016's iteration, warm-started from the cluster's rotation of
  /// the previous step, ~0.07 us per iteration; with few iterations the rotation lags a fast
  /// spin by a little, converging over the next steps.
  Rotation rotation = Rotation::kQuaternion;
  /// The most quaternion iterations per cluster and step (each stops early once the correction
  /// is below 1e-12 rad). More: closer to the exact rotation, dearer.
  int rotation_iterations = 2;
  /// Whether the goals keep each cluster's volume: the linear part A of the fit divided by
  /// cbrt(det A) (Mueller 2005's volume conservation for linear goals, applied to the linear
  /// block of quadratic ones too). Without it a body hanging from a band stretches: the
  /// clusters' fits take up the stretch as their own shape.
  bool preserve_volume = true;
  /// Match-and-pull passes per step, each from where the last left the particles, as position-
  /// based engines iterate their constraints (1: Mueller 2005's and the thesis's single pull).
  /// One pull a step moves a particle by a fraction alpha of its goal's offset, and a body's
  /// weight reaches its anchors only through the clusters' overlaps, one cluster a pass: with
  /// one pass the thesis's liver hanging from its ligament band gains 59% of its volume (144%
  /// without preserve_volume), with 4 under 10%. Each pass costs about a single-pass step.
  int iterations = 4;
  /// Set by `softbench calibrate` (alpha and beta fitted to a reference); null otherwise.
  std::optional<CalibrationRecord> calibrated;
};

/// The registry entry ("shape_matching") with the parameter table.
ModelInfo shape_matching_info();

/// Direct construction, for tests and benchmarks. Throws InputError on invalid parameters or
/// material (only its density is used).
std::unique_ptr<SoftBody> make_shape_matching(const TetMesh& mesh,
                                              const Material& material,
                                              const ShapeMatchingParams& params);

}  // namespace softbench
