// SPDX-License-Identifier: MIT
#include "harness/run/loading.h"

#include "geometry/input_error.h"

#include "geometry/mesh_topology.h"
#include "scenes/instrument_path.h"
#include "scenes/scene_regions.h"

#include <algorithm>

namespace softbench::harness {
namespace {

// A contact vertex that ends this far from the instrument has floated away from it: well past
// the margin the contact keeps, small against the mesh's edges.
double lost_contact_distance(double margin) {
  return std::max(5.0 * margin, 1e-3);
}

}  // namespace

Loading::Loading(const scenes::Scene& scene, const SceneMesh& scene_mesh) : scene_(scene) {
  const TetMesh& mesh = scene_mesh.body;
  for (int vertex : scenes::fixed_vertices(scene, mesh)) {
    fixed_.push_back({vertex, mesh.rest_positions().col(vertex)});
  }
  for (const scenes::SupportedVertex& supported : scenes::supported_vertices(scene, mesh)) {
    fixed_.push_back(
        {supported.vertex, mesh.rest_positions().col(supported.vertex), kExact, supported.held});
  }
  grasped_ = scenes::grasped_vertices(scene, mesh);
  if (scene.instrument) {
    collision::InstrumentContactOptions options;
    options.margin = scene.instrument->contact_margin;
    try {
      contact_ = std::make_unique<collision::InstrumentContact>(
          mesh.rest_positions(), boundary_triangles(mesh.tets()), *scene_mesh.instrument, options);
    } catch (const InputError& error) {
      throw InputError(scene.instrument->mesh.string() + ": " + error.what());
    }
  }
  const auto vertices = static_cast<std::size_t>(mesh.num_vertices());
  in_contact_.assign(vertices, false);
  held_.assign(vertices, 0);
  support_slot_.assign(vertices, -1);
  for (std::size_t k = 0; k < fixed_.size(); ++k) {
    if (fixed_[k].slides()) {
      support_slot_[static_cast<std::size_t>(fixed_[k].vertex)] = static_cast<int>(k);
    }
  }
  lost_.assign(vertices, false);
  constraints_.reserve(fixed_.size() + grasped_.size());
}

Loading::~Loading() = default;

bool Loading::grasp_holds(double time) const {
  if (scene_.grasp) {
    return time >= scene_.grasp->start && time < scene_.grasp->release;
  }
  if (scene_.instrument && scene_.instrument->grasp) {
    return time >= scene_.instrument->grasp->start && time < scene_.instrument->grasp->release;
  }
  return false;
}

Eigen::Vector3d Loading::tool_origin(double time) const {
  return scenes::instrument_pose(*scene_.instrument, time).translation();
}

std::span<const PositionConstraint> Loading::constraints(double start,
                                                         double dt,
                                                         const Eigen::Matrix3Xd& positions,
                                                         const Eigen::Matrix3Xd& velocities,
                                                         const Eigen::Matrix3Xd& last_forces) {
  const double end = start + dt;
  constraints_.assign(fixed_.begin(), fixed_.end());
  loaded_.clear();
  const bool holding = grasp_holds(start + 0.5 * dt);
  if (!holding) {
    grasp_anchor_.resize(3, 0);
  } else {
    const bool closes = grasp_anchor_.cols() == 0;
    if (closes) {
      grasp_anchor_.resize(3, static_cast<Eigen::Index>(grasped_.size()));
    }
    // The scene's grasp moves the patch by its path's offset; the instrument's carries it
    // rigidly in the tool's frame.
    const Eigen::Isometry3d to_tool_then =
        scene_.instrument ? scenes::instrument_pose(*scene_.instrument, start).inverse()
                          : Eigen::Isometry3d::Identity();
    const Eigen::Isometry3d tool_now = scene_.instrument
                                           ? scenes::instrument_pose(*scene_.instrument, end)
                                           : Eigen::Isometry3d::Identity();
    const Eigen::Vector3d offset =
        scene_.grasp ? scenes::grasp_offset(*scene_.grasp, end) : Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < grasped_.size(); ++i) {
      const auto column = static_cast<Eigen::Index>(i);
      if (closes) {
        grasp_anchor_.col(column) = to_tool_then * positions.col(grasped_[i]);
      }
      constraints_.push_back({grasped_[i], tool_now * grasp_anchor_.col(column) + offset});
      loaded_.push_back(grasped_[i]);
    }
  }
  if (contact_) {
    held_constraints_ = constraints_.size();
    held_loaded_ = loaded_.size();
    end_pose_ = scenes::instrument_pose(*scene_.instrument, end);
    contact_->resolve(end_pose_, positions, velocities, dt, last_forces);
    add_contact_targets();
  }
  return constraints_;
}

void Loading::add_contact_targets() {
  // The fixed region and the grasp win over contact; a support shares its vertex with it (a
  // symmetry plane through the contact patch). The supports' own constraints first, as they
  // were before the last merge.
  std::copy(fixed_.begin(), fixed_.end(), constraints_.begin());
  for (std::size_t k = 0; k < held_constraints_; ++k) {
    if (!constraints_[k].slides()) {
      held_[static_cast<std::size_t>(constraints_[k].vertex)] = 1;
    }
  }
  constraints_.resize(held_constraints_);
  loaded_.resize(held_loaded_);
  for (const collision::VertexTarget& target : contact_->targets()) {
    const auto v = static_cast<std::size_t>(target.vertex);
    if (held_[v] != 0) {
      continue;
    }
    loaded_.push_back(target.vertex);
    if (const int slot = support_slot_[v]; slot >= 0) {
      merge_contact(constraints_[static_cast<std::size_t>(slot)], target);
      continue;
    }
    // Frictionless: held along the contact normal only, free to slide along the instrument.
    constraints_.push_back({target.vertex, target.target, kExact,
                            target.slides ? PositionConstraint::along(target.push)
                                          : Eigen::Matrix3d(Eigen::Matrix3d::Identity()),
                            /*anchors=*/false});
  }
  for (std::size_t k = 0; k < held_constraints_; ++k) {
    held_[static_cast<std::size_t>(constraints_[k].vertex)] = 0;
  }
}

// The support keeps its directions and its target along them; the contact adds the part of its
// normal the support leaves free, with its target along that.
void Loading::merge_contact(PositionConstraint& support, const collision::VertexTarget& contact) {
  const Eigen::Matrix3d along_support = support.held;
  const Eigen::Vector3d free_push = contact.push - along_support * contact.push;
  if (free_push.norm() <= 1e-6) {
    return;  // the contact pushes along the support's normal only: the support holds it
  }
  support.held = along_support + PositionConstraint::along(free_push);
  support.target = contact.target + along_support * (support.target - contact.target);
}

std::optional<std::span<const PositionConstraint>> Loading::refine(
    const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& forces) {
  if (!contact_ || !contact_->refine(end_pose_, positions, forces)) {
    return std::nullopt;
  }
  add_contact_targets();
  return std::span<const PositionConstraint>(constraints_);
}

bool Loading::contact_settled(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& forces) {
  return !contact_ || !contact_->refine_would_change(end_pose_, positions, forces);
}

void Loading::observe(double end,
                      const Eigen::Matrix3Xd& positions,
                      const Eigen::Matrix3Xd& forces) {
  Eigen::Vector3d on_tissue = Eigen::Vector3d::Zero();
  for (int vertex : loaded_) {
    // At a supported vertex, what the support holds is not the tool's.
    const int slot = support_slot_[static_cast<std::size_t>(vertex)];
    on_tissue += slot < 0 ? Eigen::Vector3d(forces.col(vertex))
                          : Eigen::Vector3d(forces.col(vertex)
                                            - fixed_[static_cast<std::size_t>(slot)].held
                                                  * forces.col(vertex));
  }
  // The constraints' forces act on the tissue; the tissue pushes the tool back.
  tool_force_ = -on_tissue;
  if (scene_.grasp) {
    tool_displacement_ = scenes::grasp_offset(*scene_.grasp, end).norm();
  }
  if (!contact_) {
    return;
  }
  const scenes::Instrument& instrument = *scene_.instrument;
  tool_displacement_ =
      end <= instrument.start ? 0.0 : (tool_origin(end) - tool_origin(instrument.start)).norm();
  const Eigen::Isometry3d pose = scenes::instrument_pose(instrument, end);
  max_triangle_pairs_ = std::max(max_triangle_pairs_, contact_->count_triangle_pairs(positions));
  const double penetration = contact_->measure(pose, positions).max_penetration;
  max_penetration_ = std::max(max_penetration_, penetration);
  if (end > instrument.start && end <= instrument.release) {
    max_penetration_pressing_ = std::max(max_penetration_pressing_, penetration);
  }

  // Floating away: a vertex the instrument pressed that ends well clear of it while the
  // instrument still presses (a grasping instrument pulls; its neighbours may part from it).
  const bool pressing = !instrument.grasp && end > instrument.start && end < instrument.release;
  if (!pressing) {
    return;
  }
  // In contact: held against the instrument at the margin (a vertex a triangle push moved may
  // lie far from it).
  for (int vertex : loaded_) {
    if (contact_->instrument_distance(pose, positions.col(vertex))
        <= 2.0 * instrument.contact_margin) {
      in_contact_[static_cast<std::size_t>(vertex)] = true;
    }
  }
  const double lost_distance = lost_contact_distance(instrument.contact_margin);
  for (std::size_t vertex = 0; vertex < in_contact_.size(); ++vertex) {
    if (in_contact_[vertex] && !lost_[vertex]
        && contact_->instrument_distance(pose, positions.col(static_cast<Eigen::Index>(vertex)))
               > lost_distance) {
      lost_[vertex] = true;
    }
  }
}

int Loading::lost_contact_vertices() const {
  return static_cast<int>(std::count(lost_.begin(), lost_.end(), true));
}

}  // namespace softbench::harness
