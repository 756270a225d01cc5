// SPDX-License-Identifier: MIT
// The legacy world: btSoftRigidDynamicsWorld with the position-based btSoftBody solver.
#include "models/bullet/bullet_body.h"
#include "models/bullet/bullet_vectors.h"
#include "models/bullet/bullet_soft_body.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>

#include <algorithm>
#include <limits>

namespace softbench::bullet {
namespace {

class SoftBodyWorld final : public BulletWorld {
 public:
  SoftBodyWorld(const BulletMesh& mesh, const BulletSoftBodyParams& params)
      : iterations_(params.position_iterations) {
    btSoftBodyWorldInfo& info = world_.getWorldInfo();
    info.m_sparsesdf.Initialize();
    body_ = make_soft_body(info, mesh, params.stiffness);
    btSoftBody::Config& config = body_->m_cfg;
    config.piterations = params.position_iterations;
    config.kDP = params.damping;
    config.kVC = params.volume_conservation;
    if (params.volume_conservation > 0.0) {
      btSoftBodyHelpers::generateBoundaryFaces(body_.get());  // kVC acts on the closed surface
    }
    if (params.clusters > 0) {
      // Local shape matching: each cluster pulls its nodes toward its own rigid frame.
      body_->generateClusters(std::min(params.clusters, body_->m_nodes.size()));
      for (int c = 0; c < body_->m_clusters.size(); ++c) {
        body_->m_clusters[c]->m_matching = params.pose_matching;
      }
    } else {
      config.kMT = params.pose_matching;
    }
    if (config.kMT > 0.0 || config.kVC > 0.0) {
      body_->setPose(/*bvolume=*/config.kVC > 0.0, /*bframe=*/config.kMT > 0.0);
    }
    world_.addSoftBody(body_.get());
  }

  ~SoftBodyWorld() override { world_.removeSoftBody(body_.get()); }
  SoftBodyWorld(const SoftBodyWorld&) = delete;
  SoftBodyWorld& operator=(const SoftBodyWorld&) = delete;

  btSoftBody& body() override { return *body_; }

  void set_gravity(const Eigen::Vector3d& gravity) override {
    world_.setGravity(to_bullet(gravity));
    world_.getWorldInfo().m_gravity = to_bullet(gravity);  // the soft body reads this one
  }

  void set_loads(const Eigen::Matrix3Xd* external_forces,
                 std::span<const PenaltySpring> springs) override {
    // Accumulated in m_f, applied explicitly in predictMotion (v += dt f / m), then cleared.
    if (external_forces != nullptr) {
      for (int i = 0; i < body_->m_nodes.size(); ++i) {
        body_->addForce(to_bullet(external_forces->col(i)), i);
      }
    }
    for (const PenaltySpring& spring : springs) {
      const btVector3 gap = to_bullet(spring.target) - body_->m_nodes[spring.node].m_x;
      body_->addForce(gap * spring.stiffness, spring.node);
    }
  }

  Counters advance(double dt) override {
    world_.stepSimulation(dt, 1, dt);
    return {iterations_, 0};
  }

  std::optional<Eigen::Matrix3Xd> internal_forces() override { return std::nullopt; }

  double elastic_energy(const Eigen::Matrix3Xd& /*positions*/) const override {
    return std::numeric_limits<double>::quiet_NaN();  // links are projections, not springs
  }

  std::size_t memory_bytes() const override {
    return static_cast<std::size_t>(body_->m_nodes.size()) * sizeof(btSoftBody::Node)
           + static_cast<std::size_t>(body_->m_links.size()) * sizeof(btSoftBody::Link)
           + static_cast<std::size_t>(body_->m_tetras.size()) * sizeof(btSoftBody::Tetra)
           + static_cast<std::size_t>(body_->m_faces.size()) * sizeof(btSoftBody::Face);
  }

 private:
  // Declaration order is destruction order in reverse: the world goes before what it points to.
  btSoftBodyRigidBodyCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_{&configuration_};
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver constraint_solver_;
  btSoftRigidDynamicsWorld world_{&dispatcher_, &broadphase_, &constraint_solver_, &configuration_};
  std::unique_ptr<btSoftBody> body_;
  int iterations_;
};

}  // namespace

std::unique_ptr<BulletWorld> make_softbody_world(const BulletMesh& mesh,
                                                 const BulletSoftBodyParams& params) {
  return std::make_unique<SoftBodyWorld>(mesh, params);
}

}  // namespace softbench::bullet
