// SPDX-License-Identifier: MIT
// Sliding (frictionless) constraints, PositionConstraint::normal: a vertex held on a plane and
// free in it. Checked two ways: every model lets a body glide along a frictionless floor as if
// nothing held it, and the material-law models compress a block between two frictionless plates
// to the analytic uniaxial answer, which full (sticking) holds do not reach.
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "models/model_registry.h"
#include "models/soft_body.h"
#include "tests/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace softbench {
namespace {

/// 8 x 8 x 4 cm in 2 cm cubes.
const TetMesh& block() {
  static const TetMesh mesh = make_tet_mesh(test::box_tets(4, 4, 2, 0.08, 0.08, 0.04));
  return mesh;
}

const Material kSlidingMaterial{3000.0, 0.3, 1060.0};
constexpr double kSlidingDt = 1.0 / 60.0;
const Eigen::Vector3d kUp(0.0, 0.0, 1.0);

/// Every vertex of the face z = `z` of the block on the plane z = `height`, held along z only
/// (`slide`) or fully at its rest x, y.
std::vector<PositionConstraint> plate(double z, double height, bool slide) {
  std::vector<PositionConstraint> constraints;
  const Eigen::Matrix3Xd& rest = block().rest_positions();
  for (int v = 0; v < block().num_vertices(); ++v) {
    if (std::abs(rest(2, v) - z) < 1e-12) {
      PositionConstraint c{v, Eigen::Vector3d(rest(0, v), rest(1, v), height), kExact};
      if (slide) {
        c.held = PositionConstraint::along(kUp);
      }
      constraints.push_back(c);
    }
  }
  return constraints;
}

class SlidingConstraint : public ::testing::TestWithParam<std::string> {};

TEST_P(SlidingConstraint, ABodyGlidesAlongAFrictionlessFloor) {
  // Damping that brakes the body as a whole off (as for a free translation): the floor may
  // take no momentum along itself, so the body keeps its velocity and every vertex travels v t.
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [key, value] : builtin_models().at(GetParam()).settling_damping.items()) {
    params[key] = 0.0;
  }
  const std::unique_ptr<SoftBody> body =
      builtin_models().at(GetParam()).create(block(), kSlidingMaterial, params, ParamSource{});
  const Eigen::Vector3d velocity(0.3, -0.2, 0.0);  // m/s, along the floor
  body->set_velocities(velocity.replicate(1, block().num_vertices()));
  const std::vector<PositionConstraint> floor = plate(0.0, 0.0, /*slide=*/true);
  StepInput input;
  input.gravity.setZero();
  input.constraints = floor;
  constexpr int kSteps = 30;
  for (int step = 0; step < kSteps; ++step) {
    ASSERT_TRUE(body->step(kSlidingDt, input).finite) << "step " << step;
    for (const PositionConstraint& c : floor) {
      ASSERT_NEAR(body->positions()(2, c.vertex), 0.0, 1e-12) << "vertex " << c.vertex;
    }
  }
  // A floor that held its vertices where they were (sticking) would keep them 15 cm behind.
  const Eigen::Matrix3Xd expected =
      block().rest_positions().colwise() + kSteps * kSlidingDt * velocity;
  EXPECT_LT((body->positions() - expected).colwise().norm().maxCoeff(), 1e-6);
  EXPECT_LT(body->constraint_forces().colwise().norm().maxCoeff(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(AllModels,
                         SlidingConstraint,
                         ::testing::ValuesIn(builtin_models().names()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return param.param;
                         });

struct Compression {
  double force = 0.0;          ///< N: the top plate's reactions, summed along -z
  double bottom_force = 0.0;   ///< N: the bottom plate's, along +z
  double lateral_strain = 0.0; ///< the top face's change of width in x, relative
  double tangential = 0.0;     ///< N: the largest tangential reaction at a plate vertex
};

/// The block squeezed by `strain` between its bottom and top plates, no gravity, settled with
/// the model's settling damping.
Compression compress(const std::string& model, double strain, bool slide) {
  const std::unique_ptr<SoftBody> body = builtin_models().at(model).create(
      block(), kSlidingMaterial, builtin_models().at(model).settling_damping, ParamSource{});
  const double height = 0.04;
  std::vector<PositionConstraint> plates = plate(0.0, 0.0, slide);
  const std::vector<PositionConstraint> top = plate(height, height * (1.0 - strain), slide);
  const std::size_t bottom_count = plates.size();
  plates.insert(plates.end(), top.begin(), top.end());
  StepInput input;
  input.gravity.setZero();
  input.constraints = plates;
  for (int step = 0; step < 300; ++step) {  // 5 s: at rest to 1e-6 of the force
    EXPECT_TRUE(body->step(kSlidingDt, input).finite);
  }
  const Eigen::Matrix3Xd forces = body->constraint_forces();
  Compression result;
  double min_x = 1e9;
  double max_x = -1e9;
  for (std::size_t k = 0; k < plates.size(); ++k) {
    const int v = plates[k].vertex;
    (k < bottom_count ? result.bottom_force : result.force) +=
        (k < bottom_count ? 1.0 : -1.0) * forces(2, v);
    result.tangential = std::max(result.tangential, forces.col(v).head<2>().norm());
    if (k >= bottom_count) {
      min_x = std::min(min_x, body->positions()(0, v));
      max_x = std::max(max_x, body->positions()(0, v));
    }
  }
  result.lateral_strain = (max_x - min_x) / 0.08 - 1.0;
  return result;
}

TEST(SlidingPlates, SqueezeABlockToTheUniaxialAnswer) {
  // Between frictionless plates the strain is uniform: sigma = E epsilon, the width grows by
  // nu epsilon. Linear tets reproduce a uniform strain exactly (the patch test), so the
  // corotational FEM is off only by its solver's stopping error and the rotations' (0.1%
  // allowed); the neo-Hookean material's stress at 1% strain differs from Hookean by O(epsilon)
  // (1.5% allowed).
  constexpr double kStrain = 0.01;
  const double area = 0.08 * 0.08;
  const double uniaxial = kSlidingMaterial.young_modulus * area * kStrain;
  for (const auto& [model, tolerance] :
       std::vector<std::pair<std::string, double>>{{"corotational_fem", 1e-3},
                                                   {"neo_hookean", 1.5e-2}}) {
    const Compression sliding = compress(model, kStrain, /*slide=*/true);
    EXPECT_NEAR(sliding.force / uniaxial, 1.0, tolerance) << model;
    EXPECT_NEAR(sliding.bottom_force / uniaxial, 1.0, tolerance) << model;
    EXPECT_NEAR(sliding.lateral_strain / (kSlidingMaterial.poisson_ratio * kStrain), 1.0,
                10.0 * tolerance)
        << model;
    EXPECT_LT(sliding.tangential, 1e-12 * uniaxial) << model;
    // Held fully, the plates keep the faces from widening and the block is stiffer than the
    // material: the difference the sliding constraint exists for.
    const Compression sticking = compress(model, kStrain, /*slide=*/false);
    ::testing::Test::RecordProperty(model + "_sliding_force_over_uniaxial",
                                    std::to_string(sliding.force / uniaxial));
    ::testing::Test::RecordProperty(model + "_lateral_strain_over_nu_strain",
                                    std::to_string(sliding.lateral_strain
                                                   / (kSlidingMaterial.poisson_ratio * kStrain)));
    ::testing::Test::RecordProperty(model + "_sticking_force_over_uniaxial",
                                    std::to_string(sticking.force / uniaxial));
    EXPECT_GT(sticking.force / uniaxial, 1.05) << model;
  }
}

}  // namespace
}  // namespace softbench
