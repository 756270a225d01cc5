// SPDX-License-Identifier: MIT
// The deformable world: btDeformableMultiBodyDynamicsWorld with one elastic force, gravity, and
// the adapter's load force (external forces and penalty springs).
#include "models/bullet/bullet_body.h"
#include "models/bullet/bullet_vectors.h"
#include "models/bullet/bullet_energy.h"
#include "models/bullet/bullet_soft_body.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableCorotatedForce.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableMassSpringForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btDeformableNeoHookeanForce.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>

#include <vector>

namespace softbench::bullet {
namespace {

using Params = BulletDeformableParams;
using TVStack = btAlignedObjectArray<btVector3>;

/// Bullet's solver with its CG and Newton settings made settable (they are protected).
class ConfigurableSolver final : public btDeformableBodySolver {
 public:
  void configure(const Params& params) {
    m_cg.setTolerance(params.cg_tolerance);
    m_cg.m_maxIterations = params.cg_max_iterations;
    m_maxNewtonIterations = params.newton_iterations;
  }
};

/// External forces and penalty springs as one Lagrangian force, so Bullet integrates them with
/// its own scheme. Typed as Bullet's mouse-picking force (its penalty spring to a target), which
/// Bullet always integrates implicitly: in the residual and, with Hessian -k I, in the system
/// matrix, in both schemes. It also counts the step's Krylov work: Bullet computes the residual
/// (addScaledForces) before each solve and applies its matrix (addScaledDampingForceDifferential
/// on every force) once per CG iteration plus once per solve.
class LoadForce final : public btDeformableLagrangianForce {
 public:
  void set(const Eigen::Matrix3Xd* external_forces, std::span<const PenaltySpring> springs) {
    constant_.clear();
    if (external_forces != nullptr) {
      constant_.resize(static_cast<std::size_t>(external_forces->cols()));
      for (std::size_t i = 0; i < constant_.size(); ++i) {
        constant_[i] = to_bullet(external_forces->col(static_cast<Eigen::Index>(i)));
      }
    }
    springs_.assign(springs.begin(), springs.end());
    products_ = 0;
    solves_ = 0;
    residual_pending_ = false;
  }
  int products() const { return products_; }
  int solves() const { return solves_; }

  void addScaledForces(btScalar scale, TVStack& force) override {
    residual_pending_ = true;
    const btSoftBody& body = *m_softBodies[0];
    for (std::size_t i = 0; i < constant_.size(); ++i) {
      force[body.m_nodes[static_cast<int>(i)].index] += scale * constant_[i];
    }
    for (const PenaltySpring& spring : springs_) {
      const btSoftBody::Node& node = body.m_nodes[spring.node];
      // m_q: the solver's trial position (x_n + dt v in the Newton iteration).
      force[node.index] += (scale * spring.stiffness) * (to_bullet(spring.target) - node.m_q);
    }
  }
  // Integrated implicitly through addScaledForces in both schemes (see the class comment).
  void addScaledExplicitForce(btScalar /*scale*/, TVStack& /*force*/) override {}
  void addScaledDampingForce(btScalar /*scale*/, TVStack& /*force*/) override {}
  void addScaledDampingForceDifferential(btScalar /*scale*/,
                                         const TVStack& /*dv*/,
                                         TVStack& /*df*/) override {
    ++products_;
    if (residual_pending_) {
      ++solves_;
      residual_pending_ = false;
    }
  }
  void buildDampingForceDifferentialDiagonal(btScalar /*scale*/, TVStack& /*diag*/) override {}
  void addScaledElasticForceDifferential(btScalar scale, const TVStack& dx, TVStack& df) override {
    const btSoftBody& body = *m_softBodies[0];
    for (const PenaltySpring& spring : springs_) {
      const int index = body.m_nodes[spring.node].index;
      df[index] -= (scale * spring.stiffness) * dx[index];  // d(k (t - x)) = -k dx
    }
  }
  double totalElasticEnergy(btScalar /*dt*/) override {  // for Bullet's line search
    const btSoftBody& body = *m_softBodies[0];
    double energy = 0.0;
    for (std::size_t i = 0; i < constant_.size(); ++i) {
      energy -= constant_[i].dot(body.m_nodes[static_cast<int>(i)].m_q);
    }
    for (const PenaltySpring& spring : springs_) {
      energy += 0.5 * spring.stiffness
                * (to_bullet(spring.target) - body.m_nodes[spring.node].m_q).length2();
    }
    return energy;
  }
  btDeformableLagrangianForceType getForceType() override { return BT_MOUSE_PICKING_FORCE; }

 private:
  std::vector<btVector3> constant_;
  std::vector<PenaltySpring> springs_;
  int products_ = 0;
  int solves_ = 0;
  bool residual_pending_ = false;
};

/// The Lame parameters Bullet's force gets. Its stable neo-Hookean energy linearises to
/// mu_eff = 3/4 mu and lambda_eff = lambda - 5/8 mu; Smith et al. (2018, section 3.4) invert that.
LameParameters force_lame_parameters(const Material& material, const Params& params) {
  const LameParameters lame = lame_parameters(material);
  if (params.force != Params::Force::kNeoHookean
      || params.lame_mapping == Params::LameMapping::kDirect) {
    return lame;
  }
  return {lame.lambda + 5.0 / 6.0 * lame.mu, 4.0 / 3.0 * lame.mu};
}

double mean_edge_length(const BulletMesh& mesh) {
  double sum = 0.0;
  for (Eigen::Index e = 0; e < mesh.edges.cols(); ++e) {
    sum += (mesh.rest_positions.col(mesh.edges(1, e)) - mesh.rest_positions.col(mesh.edges(0, e)))
               .norm();
  }
  return mesh.edges.cols() > 0 ? sum / static_cast<double>(mesh.edges.cols()) : 0.0;
}

class DeformableWorld final : public BulletWorld {
 public:
  DeformableWorld(const BulletMesh& mesh, const Material& material, const Params& params)
      : energy_(make_energy(mesh, material, params)) {
    const LameParameters lame = force_lame_parameters(material, params);
    switch (params.force) {
      case Params::Force::kNeoHookean:
        elastic_ =
            std::make_unique<btDeformableNeoHookeanForce>(lame.mu, lame.lambda, params.damping);
        break;
      case Params::Force::kCorotated:
        elastic_ = std::make_unique<btDeformableCorotatedForce>(lame.mu, lame.lambda);
        break;
      case Params::Force::kMassSpring:
        elastic_ = std::make_unique<btDeformableMassSpringForce>(
            spring_stiffness(mesh, material, params), params.spring_damping,
            /*conserve_angular=*/true);
        break;
    }
    solver_.configure(params);
    constraint_solver_.setDeformableSolver(&solver_);
    world_.setImplicit(params.implicit);
    world_.setLineSearch(params.line_search);
    // Always: the default path (conjugate residual, Lagrange multipliers) gives zero motion
    // under the implicit scheme in 3.24; this one is CG with the mass preconditioner.
    world_.setUseProjection(true);

    body_ = make_soft_body(world_.getWorldInfo(), mesh, 1.0);
    // What btSoftBodyHelpers::CreateFromTetGenData does for the deformable forces.
    body_->initializeDmInverse();
    btSoftBody::TetraScratch zero;
    zero.m_F.setZero();
    zero.m_trace = 0.0;
    zero.m_J = 0.0;
    zero.m_cofF.setZero();
    zero.m_corotation.setZero();
    body_->m_tetraScratches.resize(body_->m_tetras.size(), zero);
    body_->m_tetraScratchesTn.resize(body_->m_tetras.size(), zero);
    world_.addSoftBody(body_.get());
    world_.addForce(body_.get(), &gravity_);
    world_.addForce(body_.get(), elastic_.get());
    world_.addForce(body_.get(), &loads_);
  }

  ~DeformableWorld() override { world_.removeSoftBody(body_.get()); }
  DeformableWorld(const DeformableWorld&) = delete;
  DeformableWorld& operator=(const DeformableWorld&) = delete;

  btSoftBody& body() override { return *body_; }

  void set_gravity(const Eigen::Vector3d& gravity) override {
    world_.setGravity(to_bullet(gravity));
    world_.getWorldInfo().m_gravity = to_bullet(gravity);
    gravity_.m_gravity = to_bullet(gravity);  // the force the solver integrates
  }

  void set_loads(const Eigen::Matrix3Xd* external_forces,
                 std::span<const PenaltySpring> springs) override {
    loads_.set(external_forces, springs);
  }

  Counters advance(double dt) override {
    world_.stepSimulation(dt, 1, dt);
    return {loads_.products() - loads_.solves(), loads_.solves()};
  }

  std::optional<Eigen::Matrix3Xd> internal_forces() override {
    body_->updateDeformation();  // F at m_q, which the step left equal to m_x
    TVStack forces;
    forces.resize(body_->m_nodes.size(), btVector3(0, 0, 0));
    elastic_->addScaledForces(1.0, forces);
    Eigen::Matrix3Xd result(3, body_->m_nodes.size());
    for (int i = 0; i < body_->m_nodes.size(); ++i) {
      const btVector3& f = forces[body_->m_nodes[i].index];
      result.col(i) = to_eigen(f);
    }
    return result;
  }

  double elastic_energy(const Eigen::Matrix3Xd& positions) const override {
    return energy_(positions);
  }

  std::size_t memory_bytes() const override {
    const auto tets = static_cast<std::size_t>(body_->m_tetras.size());
    return static_cast<std::size_t>(body_->m_nodes.size())
               * (sizeof(btSoftBody::Node) + 6 * sizeof(btVector3))  // + the solver's vectors
           + static_cast<std::size_t>(body_->m_links.size()) * sizeof(btSoftBody::Link)
           + tets * (sizeof(btSoftBody::Tetra) + 2 * sizeof(btSoftBody::TetraScratch))
           + energy_.memory_bytes();
  }

 private:
  static double spring_stiffness(const BulletMesh& mesh,
                                 const Material& material,
                                 const Params& params) {
    return params.spring_stiffness > 0.0 ? params.spring_stiffness
                                         : material.young_modulus * mean_edge_length(mesh);
  }

  static ElasticEnergy make_energy(const BulletMesh& mesh,
                                   const Material& material,
                                   const Params& params) {
    const LameParameters lame = force_lame_parameters(material, params);
    const ElasticEnergy::Kind kind =
        params.force == Params::Force::kNeoHookean  ? ElasticEnergy::Kind::kStableNeoHookean
        : params.force == Params::Force::kCorotated ? ElasticEnergy::Kind::kCorotated
                                                    : ElasticEnergy::Kind::kMassSpring;
    return ElasticEnergy(kind, mesh, lame.mu, lame.lambda,
                         spring_stiffness(mesh, material, params));
  }

  ElasticEnergy energy_;
  // Declaration order is destruction order in reverse: the world goes before what it points to
  // (Bullet's solver keeps raw pointers to the forces and deletes none of them).
  btDeformableGravityForce gravity_{btVector3(0, 0, 0)};
  std::unique_ptr<btDeformableLagrangianForce> elastic_;
  LoadForce loads_;
  btSoftBodyRigidBodyCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_{&configuration_};
  btDbvtBroadphase broadphase_;
  ConfigurableSolver solver_;
  btDeformableMultiBodyConstraintSolver constraint_solver_;
  btDeformableMultiBodyDynamicsWorld world_{&dispatcher_, &broadphase_, &constraint_solver_,
                                            &configuration_, &solver_};
  std::unique_ptr<btSoftBody> body_;
};

}  // namespace

std::unique_ptr<BulletWorld> make_deformable_world(const BulletMesh& mesh,
                                                   const Material& material,
                                                   const BulletDeformableParams& params) {
  return std::make_unique<DeformableWorld>(mesh, material, params);
}

}  // namespace softbench::bullet
