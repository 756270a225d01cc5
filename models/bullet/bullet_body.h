// SPDX-License-Identifier: MIT
#pragma once

// The adapter core shared by the two Bullet models (private to models/bullet/). Bullet types are
// only forward-declared here; the worlds that hold them live in bullet_softbody_world.cpp and
// bullet_deformable_world.cpp. What is common (mesh loading, constraints, copy-back, stability,
// reactions) is written once in BulletBody; what differs is behind BulletWorld.

#include "geometry/tet_mesh.h"
#include "models/material.h"
#include "models/soft_body.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

class btSoftBody;
struct btSoftBodyWorldInfo;

namespace softbench {

struct BulletSoftBodyParams;
struct BulletDeformableParams;

namespace bullet {

/// The mesh as both Bullet models load it: Bullet's node i is vertex i.
struct BulletMesh {
  Eigen::Matrix3Xd rest_positions;  ///< 3 x #V, m
  Eigen::Matrix4Xi tets;            ///< 4 x #T, positively oriented (TetMesh's invariant)
  Eigen::Matrix2Xi edges;           ///< 2 x #E, the unique tet edges: Bullet's links
  Eigen::VectorXd masses;           ///< #V, kg, lumped from the density

  static BulletMesh from(const TetMesh& mesh, double density);
};

/// A btSoftBody on `mesh`: node i at vertex i with its lumped mass, one link per edge (Bullet's
/// default material, its kLST set to `link_stiffness`), the tets appended as the mesh orders
/// them; Bullet's collision detection off, never put to sleep. The caller adds it to a world.
std::unique_ptr<btSoftBody> make_soft_body(btSoftBodyWorldInfo& info,
                                           const BulletMesh& mesh,
                                           double link_stiffness);

/// A penalty constraint as a force k (target - x) on one node.
struct PenaltySpring {
  int node = -1;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< m
  double stiffness = 0.0;                            ///< N/m
};

/// One of Bullet's worlds holding the body: everything the two models do differently.
class BulletWorld {
 public:
  struct Counters {
    int iterations = 0;     ///< solver iterations of the step
    int linear_solves = 0;  ///< Krylov solves of the step
  };

  virtual ~BulletWorld() = default;
  virtual btSoftBody& body() = 0;
  /// m/s^2, for the coming steps.
  virtual void set_gravity(const Eigen::Vector3d& gravity) = 0;
  /// The next step's external forces (3 x #V, N; null = none) and penalty springs.
  virtual void set_loads(const Eigen::Matrix3Xd* external_forces,
                         std::span<const PenaltySpring> springs) = 0;
  /// One stepSimulation(dt, 1, dt).
  virtual Counters advance(double dt) = 0;
  /// N (3 x #V): the body's own (elastic + damping) forces on each node in the current state;
  /// nullopt for a solver without forces (position-based).
  virtual std::optional<Eigen::Matrix3Xd> internal_forces() = 0;
  /// J at `positions` (3 x #V); NaN for a solver without an energy.
  virtual double elastic_energy(const Eigen::Matrix3Xd& positions) const = 0;
  /// Bytes Bullet holds for the body and its forces (an estimate from the element counts).
  virtual std::size_t memory_bytes() const = 0;
};

/// Builds a fresh world holding `mesh` (at construction and on every reset).
using WorldFactory = std::function<std::unique_ptr<BulletWorld>(const BulletMesh& mesh)>;

/// The legacy btSoftRigidDynamicsWorld with the position-based btSoftBody.
std::unique_ptr<BulletWorld> make_softbody_world(const BulletMesh& mesh,
                                                 const BulletSoftBodyParams& params);
/// btDeformableMultiBodyDynamicsWorld with the elastic force of `params` from `material`.
std::unique_ptr<BulletWorld> make_deformable_world(const BulletMesh& mesh,
                                                   const Material& material,
                                                   const BulletDeformableParams& params);

/// The SoftBody both Bullet models are (the contract of bullet_soft_body.h): drives a
/// BulletWorld step by step, maps PositionConstraints onto Bullet's kinematic nodes and forces,
/// copies node states back in vertex order, and stops calling Bullet once the state is not
/// finite.
class BulletBody final : public SoftBody {
 public:
  BulletBody(std::string name, nlohmann::json parameters, BulletMesh mesh, WorldFactory make_world);
  ~BulletBody() override;

  std::string_view name() const override { return name_; }
  nlohmann::json parameters() const override { return parameters_; }
  StepStats step(double dt, const StepInput& input) override;
  void reset() override;

  const Eigen::Matrix3Xd& positions() const override { return positions_; }
  const Eigen::Matrix3Xd& velocities() const override { return velocities_; }
  /// Sets every node's m_v and m_vn (the implicit solver restarts from m_vn). The last step's
  /// velocities before it move by the same change, so constraint_forces() still reports that
  /// step. A diverged body stays diverged.
  void set_velocities(const Eigen::Matrix3Xd& velocities) override;
  void set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) override;
  /// Estimated from the last step's loads at the first call after a change of state.
  const Eigen::Matrix3Xd& constraint_forces() const override;
  double elastic_energy() const override;
  std::size_t memory_bytes() const override;

 private:
  /// The last step's loads, kept for the reaction estimate.
  struct LastStep {
    bool taken = false;
    double dt = 0.0;
    Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
    Eigen::Matrix3Xd external_forces;    ///< 3 x #V, zero when the step had none
    Eigen::Matrix3Xd velocities_before;  ///< 3 x #V, m/s
    std::vector<int> exact;              ///< exactly constrained nodes
    std::vector<PenaltySpring> penalties;
  };

  /// The reactions constraint_forces() reports, from the last step and the current state.
  Eigen::Matrix3Xd estimate_constraint_forces() const;
  /// Zero mass for nodes held exactly this step; the lumped mass back for released ones.
  void update_kinematic_nodes(const std::vector<int>& exact);

  std::string name_;
  nlohmann::json parameters_;
  BulletMesh mesh_;
  WorldFactory make_world_;
  std::unique_ptr<BulletWorld> world_;

  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xd velocities_;
  std::vector<char> kinematic_;  ///< per node: mass currently 0 because held exactly
  bool diverged_ = false;
  LastStep last_;
  mutable Eigen::Matrix3Xd constraint_forces_;  ///< estimate_constraint_forces(), kept
  mutable bool forces_estimated_ = false;       ///< whether constraint_forces_ is for this state
  // Per-step scratch, sized once.
  std::vector<char> kinematic_next_;
  std::vector<int> exact_;
  std::vector<Eigen::Vector3d> exact_targets_;
  std::vector<Eigen::Vector3d> exact_velocities_;
  std::vector<PenaltySpring> penalties_;
};

}  // namespace bullet
}  // namespace softbench
