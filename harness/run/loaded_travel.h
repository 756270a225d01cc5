// SPDX-License-Identifier: MIT
#pragma once

#include "collision/mesh_distance.h"
#include "harness/run/scene_mesh.h"
#include "scenes/scene.h"

#include <Eigen/Core>

#include <memory>

namespace softbench::harness {

/// How far the scene's tool went into the tissue while it loaded it
/// (ContactMetrics::loaded_travel): what "the tool pressed X mm" means when plausibility.h asks
/// whether the force the tool read fits.
///  - An instrument without a grasp (it presses): how far it went into the tissue's shape just
///    before it acted (the body at its start: the shape recovery is measured against), from its
///    start to its release: how deep its vertices were when it first reached into that shape plus
///    how far its origin moved on from there while still in it (or the deepest any vertex went,
///    if more). Measured against that shape, not the deformed one, so that a model whose contact
///    lets the tool through still counts as pressed.
///  - A grasp (the scene's or the instrument's): the grasped patch's largest travel while held
///    (the scene grasp's path offset; the instrument's origin from where it was when it grasped).
///  - No tool: 0.
class LoadedTravel {
 public:
  LoadedTravel(const scenes::Scene& scene, const SceneMesh& mesh);
  ~LoadedTravel();
  LoadedTravel(const LoadedTravel&) = delete;
  LoadedTravel& operator=(const LoadedTravel&) = delete;

  /// After each step: the scene time at its end, the body's positions (3 x #V) and the tool's
  /// displacement as Loading reports it.
  void observe(double time, const Eigen::Matrix3Xd& positions, double tool_displacement);
  double max() const { return max_; }  ///< m

 private:
  void press(double time, const Eigen::Matrix3Xd& positions);

  const scenes::Scene& scene_;
  const SceneMesh& mesh_;
  double start_ = scenes::kNever;    ///< s: when the tool begins to load the tissue
  double release_ = scenes::kNever;  ///< s: when it lets go
  /// The tissue's surface as it was before the tool acted (a pressing instrument only).
  std::unique_ptr<collision::MeshDistance> before_;
  Eigen::Matrix3Xi surface_;  ///< the body's boundary triangles
  bool touched_ = false;      ///< the tool has reached into that shape
  Eigen::Vector3d touch_origin_ = Eigen::Vector3d::Zero();  ///< where its origin was then
  double touch_depth_ = 0.0;                                ///< m, how deep it was then
  double max_ = 0.0;
};

}  // namespace softbench::harness
