// SPDX-License-Identifier: MIT
#include "collision/instrument_contact.h"

#include "collision/instrument_samples.h"
#include "geometry/input_error.h"
#include "geometry/mesh_topology.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace softbench::collision {
namespace {

std::vector<int> vertices_of(const Eigen::Matrix3Xi& triangles) {
  std::vector<int> vertices(triangles.data(), triangles.data() + triangles.size());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

Aabb inflated(Aabb box, double by) {
  box.min.array() -= by;
  box.max.array() += by;
  return box;
}

// The closed, consistently oriented surfaces the inside/outside signs of MeshDistance need.
void require_closed(const Eigen::Matrix3Xi& triangles, int num_vertices, const char* what) {
  const SurfaceTopology topology = surface_topology(triangles, num_vertices);
  if (!topology.closed_manifold() || !topology.oriented()) {
    throw InputError(std::string("InstrumentContact: the ") + what
                     + " is not a closed, consistently oriented surface ("
                     + std::to_string(topology.boundary_edges) + " boundary, "
                     + std::to_string(topology.non_manifold_edges) + " non-manifold, "
                     + std::to_string(topology.misoriented_edges) + " misoriented edges)");
  }
}

// Unit vector from `from` towards `to`, or `fallback` when they (nearly) coincide.
Eigen::Vector3d direction(const Eigen::Vector3d& from,
                          const Eigen::Vector3d& to,
                          const Eigen::Vector3d& fallback) {
  const Eigen::Vector3d d = to - from;
  const double length = d.norm();
  return length > 1e-12 ? Eigen::Vector3d(d / length) : fallback;
}

// Half the tissue surface's mean edge length: the instrument samples no tissue triangle can pass
// between.
double sample_spacing(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xi& triangles) {
  double total = 0.0;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      total += (positions.col(triangles(k, t)) - positions.col(triangles((k + 1) % 3, t))).norm();
    }
  }
  return 0.5 * total / static_cast<double>(std::max<Eigen::Index>(3 * triangles.cols(), 1));
}

// The share of the margin a vertex may end inside it before refine() holds it: round-off and
// the solver's stopping error, not a contact the step missed.
constexpr double kBandSlack = 0.05;
// The share of the margin an instrument point may come inside it before it pushes the tissue
// triangle under it: more than the sagitta of a tissue triangle held on a curved instrument
// at its corners (17 um for 1.2 mm edges on a 1 cm sphere).
constexpr double kPointSlack = 0.25;
// How much deeper than this step's motion can bring it an instrument point may be inside the
// tissue and still push it, in sample spacings (half mean edges, 2.4 mm on the liver): what an
// earlier step's contact left when its passes ran out. Deeper, it is behind a fold.
constexpr double kFoldDepth = 4.0;
// m: added to the reach of the tests that skip a step's contact work when tissue and instrument
// are far apart. A sample point, made from the instrument's vertices by a weighted sum, can round
// past their box by an ulp; this is a billion of those.
constexpr double kBoxSlack = 1e-9;

}  // namespace

InstrumentContact::InstrumentContact(const Eigen::Matrix3Xd& tissue_positions,
                                     const Eigen::Matrix3Xi& tissue_surface,
                                     const TriMesh& instrument,
                                     InstrumentContactOptions options)
    : options_(std::move(options)),
      tissue_surface_(tissue_surface),
      surface_vertices_(vertices_of(tissue_surface)),
      instrument_distance_(instrument.vertices, instrument.triangles, options_.instrument_schedule),
      tissue_distance_(tissue_positions, tissue_surface, options_.tissue_schedule),
      predicted_distance_(tissue_positions, tissue_surface, options_.tissue_schedule),
      instrument_tree_(instrument.vertices, instrument.triangles, options_.instrument_schedule),
      instrument_triangles_(instrument.triangles),
      instrument_local_(instrument.vertices),
      instrument_world_(instrument.vertices),
      spacing_(sample_spacing(tissue_positions, tissue_surface)),
      samples_local_(instrument_samples(instrument, spacing_)),
      clearance_(samples_local_.cols(), instrument.vertices) {
  require_closed(tissue_surface, static_cast<int>(tissue_positions.cols()), "tissue surface");
  require_closed(instrument.triangles, instrument.num_vertices(), "instrument mesh");
  const auto vertices = static_cast<std::size_t>(tissue_positions.cols());
  pressed_.assign(vertices, 0);
  dropped_.assign(vertices, 0);
  target_index_.assign(vertices, -1);
  has_move_.assign(vertices, 0);
  last_push_.assign(vertices, Eigen::Vector3d::Zero());
  move_.assign(vertices, Eigen::Vector3d::Zero());
  push_.assign(vertices, Eigen::Vector3d::Zero());
  slides_.assign(vertices, 1);
  sample_normals_local_.resize(3, samples_local_.cols());
  for (Eigen::Index i = 0; i < samples_local_.cols(); ++i) {
    sample_normals_local_.col(i) = instrument_distance_.nearest(samples_local_.col(i)).normal;
  }
}

// Whether instrument point `sample` at `pose`, `nearest` the tissue's surface and inside it by
// the pseudonormal test, is behind a fold of that surface rather than in the tissue. The test
// says inside wherever the nearest triangle faces away, and on a folded or inverted patch that
// is the wrong side, however far off the point is: on a liver crumpling under a deep press,
// pushing such triangles out to the withdrawing probe's points moved a corner 12 cm in one
// step. A point in the tissue is pushing it out of the instrument (along the
// instrument's outward normal there, within 90 degrees), and no deeper than this step's motion
// of the point and of the triangle's corners (their free flight) can have brought it, plus
// kFoldDepth.
bool InstrumentContact::behind_fold(Eigen::Index sample,
                                    const Eigen::Isometry3d& pose,
                                    const MeshDistance::Nearest& nearest) const {
  const Eigen::Vector3d outward = pose.linear() * sample_normals_local_.col(sample);
  if (outward.dot(nearest.normal) >= 0.0) {
    return true;  // the push (-nearest.normal) would be into the instrument
  }
  double corners = 0.0;
  for (int k = 0; k < 3; ++k) {
    const int vertex = tissue_surface_(k, nearest.triangle);
    corners = std::max(corners, (predicted_.col(vertex) - start_.col(vertex)).norm());
  }
  const Eigen::Vector3d local = samples_local_.col(sample);
  const double reach = (start_pose_ * local - pose * local).norm() + corners + 2.0 * options_.margin
                       + kFoldDepth * spacing_;
  return -nearest.signed_distance > reach;
}

// An instrument point farther than this from the tissue's surface is skipped by
// resolve_instrument_vertices whichever side it is on. Outside: past the band (at most two
// margins) of the surface where the step starts, and of its free flight too, since free flight
// moves no point of the tissue farther than its fastest vertex. Inside: deeper than behind_fold's
// reach at its largest (the fastest instrument point's and tissue vertex's motion this step, two
// margins, kFoldDepth spacings).
double InstrumentContact::cull_radius() const {
  // Past the largest reach by a part in a million: round-off cannot tip a point over it.
  constexpr double kSlack = 1.000001;
  return kSlack * (tissue_motion_ + tool_motion_ + 2.0 * options_.margin + kFoldDepth * spacing_);
}

std::optional<MeshDistance::Nearest> InstrumentContact::search_sample(Eigen::Index i,
                                                                      const Eigen::Vector3d& point,
                                                                      double radius) {
  const std::optional<MeshDistance::Nearest> found =
      tissue_distance_.nearest_within(point, radius, nullptr, clearance_.hint(i));
  if (found) {
    clearance_.record(i, found->signed_distance, found->triangle);
  } else {
    clearance_.record_far(i, radius);
  }
  return found;
}

double InstrumentContact::instrument_distance(const Eigen::Isometry3d& pose,
                                              const Eigen::Vector3d& point) const {
  return instrument_distance_.nearest(pose.inverse() * point).signed_distance;
}

// A pressed vertex the instrument withdraws from (its surface there moving away along the contact
// normal) stays on it while it presses: an implicit model springs back within one step, faster
// than the instrument withdraws, and would land inside it. Sideways motion (a shaft sliding
// past the tissue) does not drag the vertex along.
bool InstrumentContact::follows_withdrawal(int vertex,
                                           const Eigen::Vector3d& local_point,
                                           const Eigen::Isometry3d& pose) const {
  if (!was_pressed(vertex)) {
    return false;
  }
  const Eigen::Vector3d motion = pose * local_point - last_pose_ * local_point;
  const Eigen::Vector3d& push = last_push_[static_cast<std::size_t>(vertex)];
  constexpr double kCos45 = 0.7071067811865476;
  return motion.dot(push) < -kCos45 * motion.norm();
}

bool InstrumentContact::was_pressed(int vertex) const {
  return pressed_[static_cast<std::size_t>(vertex)] != 0;
}

void InstrumentContact::propose(int vertex,
                                const Eigen::Vector3d& move,
                                const Eigen::Vector3d& push,
                                bool slides) {
  const auto v = static_cast<std::size_t>(vertex);
  if (!has_move_[v]) {
    has_move_[v] = 1;
    moved_.push_back(vertex);
  } else if (move.squaredNorm() <= move_[v].squaredNorm()) {
    return;
  }
  move_[v] = move;
  push_[v] = push;
  slides_[v] = slides ? 1 : 0;
}

// Tissue vertices inside the instrument, or pressed against it, or about to enter it: to its
// surface plus the margin. The target is found from where the vertex is now: from where it
// would be, a fast vertex could be past the middle of a thin instrument and be sent out of the
// far side.
void InstrumentContact::resolve_tissue_vertices(const Eigen::Isometry3d& pose,
                                                const Eigen::Matrix3Xd& positions) {
  const double margin = options_.margin;
  const Aabb reach = inflated(instrument_box_, 2.0 * margin);
  const Eigen::Isometry3d to_local = pose.inverse();
  for (int vertex : surface_vertices_) {
    const Eigen::Vector3d x = positions.col(vertex);
    const Eigen::Vector3d free_flight = predicted_.col(vertex);
    if (!reach.contains(x) && !reach.contains(free_flight) && !was_pressed(vertex)) {
      continue;
    }
    const Eigen::Vector3d local = to_local * x;
    const MeshDistance::Nearest nearest = instrument_distance_.nearest(local);
    const double band = was_pressed(vertex) ? 2.0 * margin : margin;
    if (nearest.signed_distance >= band
        && instrument_distance_.signed_distance(to_local * free_flight) >= band
        && !follows_withdrawal(vertex, nearest.point, pose)) {
      continue;
    }
    // Outward from the instrument at the nearest point: away from it for a point outside,
    // through the surface for a point inside.
    const Eigen::Vector3d out_local = nearest.signed_distance < 0.0
                                          ? direction(local, nearest.point, nearest.normal)
                                          : direction(nearest.point, local, nearest.normal);
    const Eigen::Vector3d target = pose * (nearest.point + margin * out_local);
    propose(vertex, target - x, pose.linear() * out_local, /*slides=*/true);
  }
}

// Instrument vertices inside the tissue (a tip between tissue vertices), or about to be: move
// the nearest surface triangle along its normal until the vertex is the margin outside.
void InstrumentContact::resolve_instrument_vertices(const Eigen::Isometry3d& pose) {
  const double margin = options_.margin;
  const Aabb reach =
      inflated(merge(tissue_distance_.bounds(), predicted_distance_.bounds()), 2.0 * margin);
  const double radius = cull_radius();
  clearance_.advance(start_, pose);
  for (Eigen::Index i = 0; i < samples_local_.cols(); ++i) {
    // Outside past the band where the step starts and in its free flight, or inside past any
    // fold's reach (cull_radius), or farther than that on either side: known without a query,
    // or even the point's place (most points, most steps).
    if (clearance_.outside_by(i, 2.0 * margin + tissue_motion_) || clearance_.inside_by(i, radius)
        || clearance_.far_by(i, radius)) {
      continue;
    }
    const Eigen::Vector3d p = pose * Eigen::Vector3d(samples_local_.col(i));
    if (!reach.contains(p)) {
      continue;
    }
    // A point farther from the surface than the radius, on either side, pushes nothing: the
    // query opens only the tree's nodes within it.
    const std::optional<MeshDistance::Nearest> found = search_sample(i, p, radius);
    if (!found) {
      continue;
    }
    const MeshDistance::Nearest& nearest = *found;
    const Eigen::Vector3i corners = tissue_surface_.col(nearest.triangle);
    const bool pressed =
        was_pressed(corners(0)) || was_pressed(corners(1)) || was_pressed(corners(2));
    // Short of the margin by its slack: a point of a curved instrument between tissue vertices
    // held at the margin (the chord's sagitta) is not a point the tissue passes.
    const double band = (pressed ? 2.0 * margin : margin) - kPointSlack * margin;
    // Free flight moves no surface point farther than tissue_motion_, nor the distance to the
    // surface: a point that far beyond the band needs no query of the predicted surface.
    if (nearest.signed_distance >= band
        && (nearest.signed_distance >= band + tissue_motion_
            || predicted_distance_.nearest(p, nullptr, nearest.triangle).signed_distance >= band)) {
      continue;
    }
    if (nearest.signed_distance < 0.0 && behind_fold(i, pose, nearest)) {
      continue;
    }
    // Move the surface point under the vertex inward by the shortfall (outward, to meet the
    // instrument, for tissue that is about to run into it).
    const double shortfall = std::max(0.0, margin - nearest.signed_distance);
    const Eigen::Vector3d inward = -nearest.normal;
    const Eigen::Vector3d& w = nearest.barycentric;
    const double weight_norm = w.squaredNorm();
    for (int corner = 0; corner < 3; ++corner) {
      if (w(corner) > 0.0) {
        propose(corners(corner), (w(corner) / weight_norm * shortfall) * inward, inward,
                /*slides=*/false);
      }
    }
  }
}

// One pass over the tissue (four before: each a few microseconds on the liver, where the
// contact's work while touching is some 150): its free flight, the start kept, the largest move
// between them (tissue_motion_, as largest_move() makes it) and the box of both.
Aabb InstrumentContact::start_step(const Eigen::Matrix3Xd& positions,
                                   const Eigen::Matrix3Xd& velocities,
                                   double dt) {
  predicted_.resize(3, positions.cols());  // same size every step: no allocation after the first
  start_.resize(3, positions.cols());
  Aabb box;
  double largest = 0.0;
  for (Eigen::Index v = 0; v < positions.cols(); ++v) {
    const Eigen::Vector3d x = positions.col(v);
    const Eigen::Vector3d flight = x + dt * velocities.col(v);
    start_.col(v) = x;
    predicted_.col(v) = flight;
    box.extend(x);
    box.extend(flight);
    largest = std::max(largest, (flight - x).squaredNorm());
  }
  tissue_motion_ = std::sqrt(largest);
  return box;
}

const std::vector<VertexTarget>& InstrumentContact::resolve(const Eigen::Isometry3d& pose,
                                                            const Eigen::Matrix3Xd& positions,
                                                            const Eigen::Matrix3Xd& velocities,
                                                            double dt,
                                                            const Eigen::Matrix3Xd& last_forces) {
  // Active set: a vertex stays pressed while last step's force pushed it away from the
  // instrument; an adhesive (pulling) force lets it go.
  for (const VertexTarget& target : targets_) {
    const auto v = static_cast<std::size_t>(target.vertex);
    pressed_[v] = last_forces.col(target.vertex).dot(target.push) > 0.0 ? 1 : 0;
    last_push_[v] = target.push;
  }
  // Contact is judged with the instrument where it will be at the step's end, and with the
  // tissue both where it is and where it would be without contact (its free flight x + dt v):
  // judging only where it is lets tissue that swings into a still instrument pass through it
  // within the step.
  const Aabb tissue_box = start_step(positions, velocities, dt);
  start_pose_ = last_pose_;
  instrument_world_ = pose * instrument_local_;
  instrument_box_ = fit_aabb(instrument_world_);
  tool_motion_ = largest_move(instrument_local_, start_pose_, pose);
  for (const int vertex : dropped_vertices_) {
    dropped_[static_cast<std::size_t>(vertex)] = 0;
  }
  dropped_vertices_.clear();
  moved_.clear();
  // Nothing held and the instrument farther than the contact's reach from the tissue, where the
  // step starts and in its free flight: no vertex or instrument point would be tested, no
  // triangle pair can intersect, and the trees are left as they are (refitted when the
  // instrument comes near). The work is then O(#V), whatever the tissue's size.
  report_.triangle_pairs = 0;
  report_.searched =
      !targets_.empty()
      || overlap(inflated(tissue_box, 2.0 * options_.margin + kBoxSlack), instrument_box_);
  if (report_.searched) {
    tissue_distance_.update(positions);
    predicted_distance_.update(predicted_);
    resolve_tissue_vertices(pose, positions);
    resolve_instrument_vertices(pose);
  }
  for (const VertexTarget& target : targets_) {
    pressed_[static_cast<std::size_t>(target.vertex)] = 0;
  }
  last_pose_ = pose;
  targets_.clear();
  for (int vertex : moved_) {
    const auto v = static_cast<std::size_t>(vertex);
    targets_.push_back({vertex, positions.col(vertex) + move_[v], push_[v], slides_[v] != 0});
    has_move_[v] = 0;
  }
  return targets_;
}

int InstrumentContact::count_triangle_pairs(const Eigen::Matrix3Xd& positions) {
  report_.triangle_pairs = 0;
  if (!report_.searched) {
    return 0;  // the instrument out of reach: no pair can intersect
  }
  // As the step's detection saw them: the tissue where the step started, the instrument where
  // it ends. The tissue's tree is then refitted back to `positions`, where the next step's
  // contact (and measure()) will find it, so the count adds no refit to the next step's work.
  instrument_world_ = last_pose_ * instrument_local_;
  instrument_tree_.refit(instrument_world_);
  tissue_distance_.update(start_);
  collide(tissue_distance_.tree(), start_, instrument_tree_, instrument_world_, buffers_, pairs_);
  tissue_distance_.update(positions);
  report_.triangle_pairs = static_cast<int>(pairs_.size());
  return report_.triangle_pairs;
}

// A target on the instrument's surface (plus the margin): a tissue vertex's own contact, not a
// corner of a triangle an instrument point pushes (whose hold is judged over the triangle).
bool InstrumentContact::on_surface(const Eigen::Isometry3d& pose,
                                   const VertexTarget& target) const {
  const double gap = instrument_distance(pose, target.target) - options_.margin;
  return std::abs(gap) <= 1e-3 * options_.margin;
}

bool InstrumentContact::refine(const Eigen::Isometry3d& pose,
                               const Eigen::Matrix3Xd& positions,
                               const Eigen::Matrix3Xd& forces) {
  bool changed = false;
  // Drop the holds that pulled: the tissue there moves away from the instrument by itself.
  std::size_t kept = 0;
  for (const VertexTarget& target : targets_) {
    if (forces.col(target.vertex).dot(target.push) < 0.0 && on_surface(pose, target)) {
      dropped_[static_cast<std::size_t>(target.vertex)] = 1;
      dropped_vertices_.push_back(target.vertex);
      changed = true;
    } else {
      targets_[kept++] = target;
    }
  }
  targets_.resize(kept);
  // Hold the surface vertices that ended inside the margin the contact keeps: where the step
  // would have put them, projected out along the instrument's surface normal to the margin.
  // Left inside the margin band, a vertex would take no force there while its neighbours on
  // the band's edge took all of it: the patch's force would jump by a vertex's share from step
  // to step. A hold dropped this step comes back only if its vertex ended inside the instrument
  // itself (the other holds' changes pushed it in); in the band it stays free, so a
  // hold that pulls cannot be taken again and again within a step.
  for (std::size_t k = 0; k < targets_.size(); ++k) {
    target_index_[static_cast<std::size_t>(targets_[k].vertex)] = static_cast<int>(k);
  }
  const double margin = options_.margin;
  const Aabb reach = inflated(instrument_box_, margin);
  const Eigen::Isometry3d to_local = pose.inverse();
  for (const int vertex : surface_vertices_) {
    const auto v = static_cast<std::size_t>(vertex);
    if (target_index_[v] >= 0 || !reach.contains(positions.col(vertex))) {
      continue;
    }
    const Eigen::Vector3d local = to_local * positions.col(vertex);
    const MeshDistance::Nearest nearest = instrument_distance_.nearest(local);
    const double allowed = dropped_[v] != 0 ? 0.0 : (1.0 - kBandSlack) * margin;
    if (nearest.signed_distance >= allowed) {
      continue;
    }
    const Eigen::Vector3d out_local = nearest.signed_distance < 0.0
                                          ? direction(local, nearest.point, nearest.normal)
                                          : direction(nearest.point, local, nearest.normal);
    target_index_[v] = static_cast<int>(targets_.size());
    targets_.push_back(
        {vertex, pose * (nearest.point + margin * out_local), pose.linear() * out_local});
    changed = true;
  }
  changed = hold_tissue_around_points(pose, positions) || changed;
  for (const VertexTarget& target : targets_) {
    target_index_[static_cast<std::size_t>(target.vertex)] = -1;
  }
  return changed;
}

bool InstrumentContact::refine_would_change(const Eigen::Isometry3d& pose,
                                            const Eigen::Matrix3Xd& positions,
                                            const Eigen::Matrix3Xd& forces) {
  // refine() changes the targets and marks the holds it drops; all of it is put back. A vertex
  // is marked exactly while it is listed in dropped_vertices_, so the marks need no copy: the
  // ones refine() added are cleared and the earlier ones set again (a hold dropped earlier this
  // step, taken back and dropped again, is listed twice).
  saved_targets_.assign(targets_.begin(), targets_.end());
  const std::size_t dropped = dropped_vertices_.size();
  const bool changed = refine(pose, positions, forces);
  targets_.swap(saved_targets_);
  for (std::size_t k = dropped; k < dropped_vertices_.size(); ++k) {
    dropped_[static_cast<std::size_t>(dropped_vertices_[k])] = 0;
  }
  dropped_vertices_.resize(dropped);
  for (const int vertex : dropped_vertices_) {
    dropped_[static_cast<std::size_t>(vertex)] = 1;
  }
  return changed;
}

// The instrument's points the tissue ended around (a thin tip the tissue sprang back over as
// the tool withdrew, faster than the tool): the triangle under each is held the margin outside
// the point, as resolve() pushes it, its corners held fully so it stays under the point.
bool InstrumentContact::hold_tissue_around_points(const Eigen::Isometry3d& pose,
                                                  const Eigen::Matrix3Xd& positions) {
  const double margin = options_.margin;
  // Every instrument point lies in the instrument's box: none can be inside tissue farther away
  // than the margin, and the tree need not be refitted to know it.
  if (!overlap(inflated(fit_aabb(positions), margin + kBoxSlack), instrument_box_)) {
    return false;
  }
  tissue_distance_.update(positions);
  const Aabb reach = inflated(tissue_distance_.bounds(), margin);
  // A point deeper than this is behind a fold (cull_radius).
  const double radius = cull_radius();
  clearance_.advance(positions, pose);
  bool changed = false;
  for (Eigen::Index i = 0; i < samples_local_.cols(); ++i) {
    if (clearance_.outside_by(i, 0.0) || clearance_.inside_by(i, radius)
        || clearance_.far_by(i, radius)) {
      continue;
    }
    const Eigen::Vector3d p = pose * Eigen::Vector3d(samples_local_.col(i));
    if (!reach.contains(p)) {
      continue;
    }
    // Only a point inside the tissue itself: one in the margin band is resolve()'s to judge at
    // the next step (a curved instrument's points come into the band between the vertices
    // held on it, and holding their triangles fully would make the contact stick). One deeper
    // than the radius is behind a fold, one outside by as much is out: neither needs its nearest
    // point.
    const std::optional<MeshDistance::Nearest> found = search_sample(i, p, radius);
    if (!found) {
      continue;
    }
    const MeshDistance::Nearest& nearest = *found;
    if (nearest.signed_distance >= 0.0) {
      continue;
    }
    if (behind_fold(i, pose, nearest)) {
      continue;
    }
    const double shortfall = margin - nearest.signed_distance;
    const Eigen::Vector3d inward = -nearest.normal;
    const Eigen::Vector3i corners = tissue_surface_.col(nearest.triangle);
    const Eigen::Vector3d& w = nearest.barycentric;
    const double weight_norm = w.squaredNorm();
    for (int corner = 0; corner < 3; ++corner) {
      const auto v = static_cast<std::size_t>(corners(corner));
      if (w(corner) <= 0.0) {
        continue;
      }
      const VertexTarget hold{
          corners(corner),
          positions.col(corners(corner)) + (w(corner) / weight_norm * shortfall) * inward, inward,
          /*slides=*/false};
      if (target_index_[v] < 0) {
        target_index_[v] = static_cast<int>(targets_.size());
        targets_.push_back(hold);
        changed = true;
        continue;
      }
      // A corner sliding along the instrument let the triangle slip past the point: held
      // fully where the push puts it. One held fully already (by an earlier pass, or by
      // another point) goes as much further along the push as this point needs.
      VertexTarget& target = targets_[static_cast<std::size_t>(target_index_[v])];
      if (target.slides) {
        target = hold;
        changed = true;
        continue;
      }
      const double further = (hold.target - target.target).dot(inward);
      if (further > 1e-3 * margin) {
        target.target += further * inward;
        changed = true;
      }
    }
  }
  return changed;
}

ContactReport InstrumentContact::measure(const Eigen::Isometry3d& pose,
                                         const Eigen::Matrix3Xd& positions) {
  ContactReport report;
  instrument_world_ = pose * instrument_local_;
  const Aabb instrument_box = fit_aabb(instrument_world_);
  if (!overlap(inflated(fit_aabb(positions), kBoxSlack), instrument_box)) {
    return report;  // apart: nothing penetrates (no tree refitted to say so)
  }
  const Eigen::Isometry3d to_local = pose.inverse();
  for (int vertex : surface_vertices_) {
    if (!instrument_box.contains(positions.col(vertex))) {
      continue;
    }
    const double depth =
        -instrument_distance_.nearest(to_local * positions.col(vertex)).signed_distance;
    if (depth > 0.0) {
      report.max_penetration = std::max(report.max_penetration, depth);
    }
  }
  tissue_distance_.update(positions);
  clearance_.advance(positions, pose);
  const Aabb tissue_box = tissue_distance_.bounds();
  for (Eigen::Index i = 0; i < samples_local_.cols(); ++i) {
    // A point known to be outside has no depth: skipped without a query.
    if (clearance_.outside_by(i, 0.0)) {
      continue;
    }
    const Eigen::Vector3d p = pose * Eigen::Vector3d(samples_local_.col(i));
    if (!tissue_box.contains(p)) {
      continue;
    }
    const MeshDistance::Nearest nearest = tissue_distance_.nearest(p, nullptr, clearance_.hint(i));
    clearance_.record(i, nearest.signed_distance, nearest.triangle);
    const double depth = -nearest.signed_distance;
    if (depth > 0.0) {
      report.max_penetration = std::max(report.max_penetration, depth);
    }
  }
  return report;
}

}  // namespace softbench::collision
