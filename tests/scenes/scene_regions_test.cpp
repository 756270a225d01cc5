// SPDX-License-Identifier: MIT
// Fixed and grasped regions on small box meshes, the grasp path, and the shipped scenes'
// regions on the shipped liver.
#include "scenes/scene_regions.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_validation.h"
#include "models/model_registry.h"
#include "scenes/instrument_path.h"
#include "scenes/scene.h"
#include "scenes/shipped_data.h"
#include "tests/test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

namespace softbench::scenes {
namespace {

// A 0.1 m box of 2 x 2 x 2 cubes: 27 vertices on a 0.05 m grid, index i + 3 j + 9 k; the centre
// vertex 13 is the only one inside.
TetMesh box_mesh() {
  return make_tet_mesh(test::box_tets(2, 2, 2, 0.1, 0.1, 0.1));
}

int grid_vertex(int i, int j, int k) {
  return i + 3 * j + 9 * k;
}

Scene box_scene() {
  Scene scene;
  scene.source = "scenes/box.json";
  scene.mesh = "scenes/box.msh";
  return scene;
}

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

TEST(FixedVertices, SelectsVerticesInsideABoxIncludingItsFaces) {
  Scene scene = box_scene();
  scene.fixed.box = Box{{-1.0, -1.0, -1.0}, {1.0, 1.0, 0.0}};  // the bottom layer, z = 0
  EXPECT_EQ(fixed_vertices(scene, box_mesh()), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(FixedVertices, SelectsAPlaneBandOnBothSidesOfThePlane) {
  Scene scene = box_scene();
  // The plane x = 0.05 with a band of 0.05 selects the whole grid; 0.01 only its middle column.
  scene.fixed.plane = Plane{{0.05, 0.0, 0.0}, {1.0, 0.0, 0.0}, 0.01};
  std::vector<int> middle;
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) {
      middle.push_back(grid_vertex(1, j, k));
    }
  }
  std::sort(middle.begin(), middle.end());
  EXPECT_EQ(fixed_vertices(scene, box_mesh()), middle);
  scene.fixed.plane->tolerance = 0.05;
  EXPECT_EQ(fixed_vertices(scene, box_mesh()).size(), 27u);
}

TEST(SupportedVertices, HoldAlongEachSupportsNormalAndLeaveTheFixedOnesFixed) {
  Scene scene = box_scene();
  scene.fixed.box = Box{{-1.0, -1.0, -1.0}, {1.0, 1.0, 0.0}};  // the bottom layer
  scene.supports = {Plane{{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, 1e-9},
                    Plane{{0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 1e-9}};
  const std::vector<SupportedVertex> supported = supported_vertices(scene, box_mesh());
  // The faces x = 0 and y = 0 above the bottom layer: 2 layers of 5 vertices.
  ASSERT_EQ(supported.size(), 10u);
  for (const SupportedVertex& s : supported) {
    EXPECT_GE(s.vertex, 9) << "a fixed vertex";
    const int i = s.vertex % 3;
    const int j = (s.vertex / 3) % 3;
    Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
    expected(0, 0) = i == 0 ? 1.0 : 0.0;
    expected(1, 1) = j == 0 ? 1.0 : 0.0;
    // On both planes (the edge x = y = 0): held across the line, free along z.
    EXPECT_TRUE(s.held.isApprox(expected, 1e-12)) << s.vertex << "\n" << s.held;
  }
}

TEST(FixedVertices, SelectsAnObliquePlaneBand) {
  Scene scene = box_scene();
  // The diagonal plane x + y = 0.1 (through the box's centre, normal (1, 1, 0)/sqrt 2), band of
  // 1 mm: the vertices with i + j = 2.
  scene.fixed.plane = Plane{{0.05, 0.05, 0.0}, Eigen::Vector3d(1.0, 1.0, 0.0).normalized(), 1e-3};
  std::vector<int> diagonal;
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 3; ++i) {
      diagonal.push_back(grid_vertex(i, 2 - i, k));
    }
  }
  std::sort(diagonal.begin(), diagonal.end());
  EXPECT_EQ(fixed_vertices(scene, box_mesh()), diagonal);
}

TEST(FixedVertices, SelectsListedVerticesSortedAndUnique) {
  Scene scene = box_scene();
  scene.fixed.vertices = {26, 3, 13, 3};
  EXPECT_EQ(fixed_vertices(scene, box_mesh()), (std::vector<int>{3, 13, 26}));
}

TEST(FixedVertices, UnitesTheListTheBoxAndThePlane) {
  Scene scene = box_scene();
  scene.fixed.vertices = {13, 0};
  scene.fixed.box = Box{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.1}};            // i = j = 0: 0, 9, 18
  scene.fixed.plane = Plane{{0.0, 0.0, 0.1}, {0.0, 0.0, -1.0}, 0.0};  // top layer: 18..26
  EXPECT_EQ(fixed_vertices(scene, box_mesh()),
            (std::vector<int>{0, 9, 13, 18, 19, 20, 21, 22, 23, 24, 25, 26}));
}

TEST(FixedVertices, RejectsAListedIndexOutOfRangeNamingItsPointer) {
  Scene scene = box_scene();
  scene.fixed.vertices = {0, 1, 2, 27};
  EXPECT_EQ(error_of([&] { fixed_vertices(scene, box_mesh()); }),
            "scenes/box.json: /fixed/vertices/3: expected a vertex index in [0, 26] "
            "(scenes/box.msh has 27 vertices), got 27");
}

TEST(FixedVertices, AreNoneForAFreeBody) {
  Scene scene = box_scene();
  EXPECT_TRUE(fixed_vertices(scene, box_mesh()).empty());
  scene.fixed.box = Box{{1.0, 1.0, 1.0}, {2.0, 2.0, 2.0}};  // misses the mesh
  EXPECT_TRUE(fixed_vertices(scene, box_mesh()).empty());
}

TEST(RequiredFixedVertices, RejectsARegionThatSelectsNothingNamingTheCommand) {
  Scene scene = box_scene();
  scene.fixed.box = Box{{1.0, 1.0, 1.0}, {2.0, 2.0, 2.0}};  // metres given as decimetres
  EXPECT_EQ(error_of([&] { required_fixed_vertices(scene, box_mesh(), "calibrate", "why"); }),
            "scenes/box.json: /fixed: selects no vertex of scenes/box.msh (its vertices span "
            "[0, 0, 0] to [0.1, 0.1, 0.1]); calibrate needs a fixed region: why");
  scene.fixed = {};
  EXPECT_EQ(error_of([&] { required_fixed_vertices(scene, box_mesh(), "calibrate", "why"); }),
            "scenes/box.json: /fixed: absent (a free body); calibrate needs a fixed region: why");
  scene.fixed.vertices = {4, 2};
  EXPECT_EQ(required_fixed_vertices(scene, box_mesh(), "calibrate", "why"),
            (std::vector<int>{2, 4}));
}

TEST(InitialVelocities, AreZeroWithoutAnInitialVelocity) {
  const Eigen::Matrix3Xd velocities = initial_velocities(box_scene(), box_mesh());
  EXPECT_EQ(velocities.cols(), 27);
  EXPECT_TRUE(velocities.isZero(0.0));
}

TEST(InitialVelocities, SpinAboutTheCentreOfMassByDefault) {
  Scene scene = box_scene();
  scene.initial_velocity = InitialVelocity{{0.1, 0.0, 0.0}, {0.0, 0.0, 2.0}, std::nullopt};
  EXPECT_TRUE(rest_centre_of_mass(box_mesh()).isApprox(Eigen::Vector3d(0.05, 0.05, 0.05), 1e-15));
  const Eigen::Matrix3Xd velocities = initial_velocities(scene, box_mesh());
  // Vertex 13 is the centre; vertex 0 at (0, 0, 0) is (-0.05, -0.05, -0.05) from it.
  EXPECT_TRUE(velocities.col(13).isApprox(Eigen::Vector3d(0.1, 0.0, 0.0), 1e-14));
  EXPECT_TRUE(
      velocities.col(grid_vertex(0, 0, 0)).isApprox(Eigen::Vector3d(0.1 + 0.1, -0.1, 0.0), 1e-14));
  // About a given center instead, with the fixed vertices at rest.
  scene.initial_velocity->center = Eigen::Vector3d::Zero();
  scene.fixed.vertices = {13};
  const Eigen::Matrix3Xd about_origin = initial_velocities(scene, box_mesh());
  EXPECT_EQ(about_origin.col(13), Eigen::Vector3d::Zero());
  EXPECT_EQ(about_origin.col(grid_vertex(0, 0, 0)), Eigen::Vector3d(0.1, 0.0, 0.0));
  EXPECT_TRUE(about_origin.col(grid_vertex(2, 0, 0))
                  .isApprox(Eigen::Vector3d(0.1, 0.2, 0.0), 1e-14));  // 2 rad/s x 0.1 m
}

TEST(GraspedVertices, SelectsSurfaceVerticesWithinTheRadius) {
  Scene scene = box_scene();
  scene.grasp = Grasp{};
  scene.grasp->center = {0.1, 0.1, 0.1};
  scene.grasp->radius = 0.05;  // the corner and its three grid neighbours, inclusive
  EXPECT_EQ(grasped_vertices(scene, box_mesh()),
            (std::vector<int>{grid_vertex(2, 2, 1), grid_vertex(2, 1, 2), grid_vertex(1, 2, 2),
                              grid_vertex(2, 2, 2)}));
}

TEST(GraspedVertices, LeavesOutInteriorVertices) {
  Scene scene = box_scene();
  scene.grasp = Grasp{};
  scene.grasp->center = {0.05, 0.05, 0.05};  // the one interior vertex, 13
  scene.grasp->radius = 0.05;                // and the six face centres around it
  EXPECT_EQ(grasped_vertices(scene, box_mesh()), (std::vector<int>{4, 10, 12, 14, 16, 22}));
}

TEST(GraspedVertices, RejectsAGraspThatReachesNoSurfaceVertex) {
  Scene scene = box_scene();
  scene.grasp = Grasp{};
  scene.grasp->center = {0.05, 0.05, 0.05};
  scene.grasp->radius = 0.01;
  EXPECT_EQ(error_of([&] { grasped_vertices(scene, box_mesh()); }),
            "scenes/box.json: /grasp: selects no surface vertex of scenes/box.msh within radius "
            "0.01 of center [0.05, 0.05, 0.05] (the nearest is 0.05 away)");
}

TEST(GraspedVertices, IsEmptyWithoutAGrasp) {
  EXPECT_TRUE(grasped_vertices(box_scene(), box_mesh()).empty());
}

TEST(GraspOffset, InterpolatesLinearlyBetweenKeyframes) {
  Grasp grasp;
  grasp.path = {{1.0, {0.0, 0.0, 0.0}}, {1.5, {0.0, 0.06, 0.0}}, {2.5, {0.0, 0.06, -0.02}}};
  EXPECT_EQ(grasp_offset(grasp, 0.0), Eigen::Vector3d::Zero());
  EXPECT_EQ(grasp_offset(grasp, 1.0), Eigen::Vector3d::Zero());
  EXPECT_TRUE(grasp_offset(grasp, 1.25).isApprox(Eigen::Vector3d(0.0, 0.03, 0.0)));
  EXPECT_EQ(grasp_offset(grasp, 1.5), Eigen::Vector3d(0.0, 0.06, 0.0));
  EXPECT_TRUE(grasp_offset(grasp, 2.0).isApprox(Eigen::Vector3d(0.0, 0.06, -0.01)));
  EXPECT_EQ(grasp_offset(grasp, 2.5), Eigen::Vector3d(0.0, 0.06, -0.02));
  EXPECT_EQ(grasp_offset(grasp, 9.0), Eigen::Vector3d(0.0, 0.06, -0.02));
}

TEST(GraspOffset, IsZeroBeforeAFirstKeyframeThatIsNotAtZero) {
  Grasp grasp;
  grasp.path = {{1.0, {0.01, 0.0, 0.0}}};
  EXPECT_EQ(grasp_offset(grasp, 0.999), Eigen::Vector3d::Zero());
  EXPECT_EQ(grasp_offset(grasp, 1.0), Eigen::Vector3d(0.01, 0.0, 0.0));
  EXPECT_EQ(grasp_offset(grasp, 3.0), Eigen::Vector3d(0.01, 0.0, 0.0));
}

TEST(GraspOffset, IsZeroWithoutKeyframes) {
  EXPECT_EQ(grasp_offset(Grasp{}, 1.0), Eigen::Vector3d::Zero());
}

// The shipped scenes: they load, their regions select sensible parts of the shipped liver, and
// their timing is what scenes/README.md says.
class ShippedSceneRegions : public ::testing::TestWithParam<std::string> {
 protected:
  static Scene load(const std::string& name) {
    return load_scene(shipped_data_dir().parent_path() / (name + ".json"));
  }
};

TEST_P(ShippedSceneRegions, LoadAndFixBetweenThreeAndFifteenPercentOfTheLiver) {
  const Scene scene = load(GetParam());
  EXPECT_EQ(scene.name, GetParam());
  const TetMesh liver = make_tet_mesh(read_mesh(scene.mesh));
  const std::size_t fixed = fixed_vertices(scene, liver).size();
  const double fraction = static_cast<double>(fixed) / liver.num_vertices();
  EXPECT_GE(fraction, 0.03) << fixed << " fixed";
  EXPECT_LE(fraction, 0.15) << fixed << " fixed";
  if (scene.grasp || (scene.instrument && scene.instrument->grasp)) {
    const std::vector<int> grasped = grasped_vertices(scene, liver);
    EXPECT_GE(grasped.size(), 8u);
    EXPECT_LE(grasped.size(), 40u);
    // The grasped patch and the fixed band do not overlap.
    const std::vector<int> held = fixed_vertices(scene, liver);
    for (const int vertex : grasped) {
      EXPECT_FALSE(std::binary_search(held.begin(), held.end(), vertex)) << vertex;
    }
  }
  EXPECT_NEAR(scene.dt, 1.0 / 60.0, 1e-15);
  ASSERT_EQ(scene.model_parameters.count("mass_spring"), 1u);
  // Every block names a registered model, which accepts it.
  for (const auto& [model, block] : scene.model_parameters) {
    ASSERT_TRUE(builtin_models().contains(model)) << model;
    EXPECT_NE(builtin_models().at(model).create(liver, scene.material, block,
                                                {scene.source.string(), "/models/" + model}),
              nullptr);
  }
  EXPECT_EQ(to_json(parse_scene(to_json(scene), scene.source)), to_json(scene));
}

INSTANTIATE_TEST_SUITE_P(Liver,
                         ShippedSceneRegions,
                         ::testing::Values("liver_gravity",
                                           "liver_pull",
                                           "liver_press",
                                           "liver_gravity_tissue",
                                           "liver_pull_tissue"));

TEST(ShippedScenes, GravitySceneSagsForHalfTheRunThenLetsGo) {
  for (const char* name : {"liver_gravity", "liver_gravity_tissue"}) {
    const Scene scene =
        load_scene(shipped_data_dir().parent_path() / (std::string(name) + ".json"));
    EXPECT_EQ(scene.gravity.off_at, 1.5);
    EXPECT_EQ(scene.duration, 3.5);
    EXPECT_EQ(scene.num_steps(), 210);
    EXPECT_EQ(scene.release_time(), 1.5);
    EXPECT_EQ(scene.reference_time(), 0.0);
    EXPECT_FALSE(scene.grasp.has_value());
  }
}

TEST(ShippedScenes, PullScenesPullThirtyPercentOfTheLiversLengthAndRelease) {
  const Scene tissue = load_scene(shipped_data_dir().parent_path() / "liver_pull_tissue.json");
  ASSERT_TRUE(tissue.grasp.has_value());
  EXPECT_EQ(grasp_offset(*tissue.grasp, 1.0), Eigen::Vector3d::Zero());
  EXPECT_NEAR(grasp_offset(*tissue.grasp, 1.5).norm(), 0.06, 1e-4);
  EXPECT_EQ(grasp_offset(*tissue.grasp, 1.5), grasp_offset(*tissue.grasp, 2.0));  // held

  // liver_pull.json grasps with the probe: the patch moves with the tool's pose.
  const Scene pull = load_scene(shipped_data_dir().parent_path() / "liver_pull.json");
  ASSERT_TRUE(pull.instrument && pull.instrument->grasp);
  const auto tool_at = [&](double t) -> Eigen::Vector3d {
    return instrument_pose(*pull.instrument, t).translation();
  };
  EXPECT_NEAR((tool_at(2.5) - tool_at(2.0)).norm(), 0.06, 1e-4);
  EXPECT_EQ(tool_at(2.5), tool_at(3.0));  // held

  EXPECT_EQ(tissue.duration, 4.0);
  EXPECT_EQ(tissue.num_steps(), 240);
  EXPECT_EQ(tissue.reference_time(), 1.0);
  EXPECT_EQ(tissue.release_time(), 2.0);
  // The probe grasps once the damped liver is at rest (2.0 s), so the shape recovery is
  // measured against is a rest shape.
  EXPECT_EQ(pull.duration, 5.0);
  EXPECT_EQ(pull.num_steps(), 300);
  EXPECT_EQ(pull.reference_time(), 2.0);
  EXPECT_EQ(pull.release_time(), 3.0);
  for (const Scene* scene : {&tissue, &pull}) {
    EXPECT_EQ(scene->gravity.off_at, kNever);
  }
}

TEST(ShippedScenes, PressScenePressesTwoCentimetresPastTheSettledSurfaceAndWithdraws) {
  const Scene press = load_scene(shipped_data_dir().parent_path() / "liver_press.json");
  ASSERT_TRUE(press.instrument.has_value());
  EXPECT_FALSE(press.instrument->grasp.has_value());
  const auto tip_at = [&](double t) -> Eigen::Vector3d {
    return instrument_pose(*press.instrument, t).translation();
  };
  // 1 cm above corotational_fem's settled surface at 2.0 s, 2 cm past it at 2.5 s, held.
  EXPECT_NEAR(tip_at(2.0).z() - tip_at(2.5).z(), 0.03, 1e-12);
  EXPECT_EQ(tip_at(2.5), tip_at(3.0));
  EXPECT_EQ(tip_at(3.5), tip_at(0.0));  // withdrawn to where it started
  EXPECT_EQ(press.reference_time(), 1.5);
  EXPECT_EQ(press.release_time(), 3.0);
}

TEST(ShippedScenes, TissueVariantsUseMeasuredLiverStiffness) {
  for (const char* name : {"liver_gravity_tissue", "liver_pull_tissue"}) {
    const Scene scene =
        load_scene(shipped_data_dir().parent_path() / (std::string(name) + ".json"));
    EXPECT_EQ(scene.material.young_modulus, 5000.0);
    EXPECT_EQ(scene.material.poisson_ratio, 0.45);
    EXPECT_EQ(scene.material.density, 1060.0);
    EXPECT_EQ(scene.model_parameters.at("mass_spring"),
              nlohmann::json::parse(R"({"stiffness_from": "young_modulus", "damping": 5.0})"));
  }
}

}  // namespace
}  // namespace softbench::scenes
