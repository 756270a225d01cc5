// SPDX-License-Identifier: MIT
// read_scene_mesh's units check: a mesh whose size is far from what the scene around it expects
// (a mesh in millimetres for a scene in metres, or the other way round) is bad input.
#include "harness/run/scene_mesh.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "harness/run/mesh_override.h"
#include "scenes/scene.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace softbench::harness {
namespace {

using ::testing::HasSubstr;

class SceneMeshUnits : public ::testing::Test {
 protected:
  SceneMeshUnits() {
    // A 10 x 2 x 2 cm bar, in metres and the same in millimetres.
    const MeshData bar = test::box_tets(5, 1, 1, 0.1, 0.02, 0.02);
    write_msh(dir_.path() / "bar.msh", bar);
    MeshData bar_mm = bar;
    bar_mm.vertices *= 1000.0;
    write_msh(dir_.path() / "bar_mm.msh", bar_mm);
  }

  // The bar clamped at x = 0 and grasped at its free end, all in metres (or in millimetres,
  // scaled by `unit`), on `mesh`.
  scenes::Scene scene(const std::string& mesh, double unit = 1.0) const {
    const auto at = [unit](double metres) { return std::to_string(metres * unit); };
    return scenes::load_scene(dir_.write("bar_pull.json", R"({
      "name": "bar_pull",
      "mesh": ")" + mesh + R"(",
      "material": {"young_modulus": 50000, "poisson_ratio": 0.3, "density": 1000},
      "time": {"dt": 0.01, "duration": 0.1},
      "fixed": {"box": {"min": [)" + at(-0.001) + ", " + at(-0.001)
                                                              + ", " + at(-0.001) + R"(],
                        "max": [)" + at(0.001) + ", " + at(0.021)
                                                              + ", " + at(0.021) + R"(]}},
      "grasp": {"center": [)" + at(0.1) + ", " + at(0.01) + ", "
                                                              + at(0.01) + R"(],
                "radius": )" + at(0.015) + R"(, "start": 0.02,
                "path": [{"t": 0.02, "offset": [0, 0, 0]},
                         {"t": 0.05, "offset": [0, 0, )" + at(0.02)
                                                              + R"(]}]}
    })"));
  }

  test::TempDir dir_;
};

TEST_F(SceneMeshUnits, ReadsAMeshInTheScenesUnits) {
  const SceneMesh mesh = read_scene_mesh(scene("bar.msh"));
  EXPECT_EQ(mesh.body.num_vertices(), 24);
  EXPECT_NEAR(mesh.diagonal(), 0.1039, 1e-4);
}

TEST_F(SceneMeshUnits, RejectsAMeshInMillimetresForASceneInMetresNamingTheFile) {
  try {
    read_scene_mesh(scene("bar_mm.msh"));
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("bar_mm.msh: its bounding-box diagonal is 104"));
    EXPECT_THAT(error.what(), HasSubstr("x larger (a mesh in millimetres for a scene in metres?)"));
    EXPECT_THAT(error.what(), HasSubstr("scenes and their meshes are in metres"));
  }
}

TEST_F(SceneMeshUnits, RejectsASceneInMillimetresForAMeshInMetres) {
  try {
    read_scene_mesh(scene("bar.msh", 1000.0));
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("bar.msh: its bounding-box diagonal is 0.104"));
    EXPECT_THAT(error.what(),
                HasSubstr("x smaller (a scene in millimetres for a mesh in metres?)"));
  }
  // Both in millimetres agree with each other (SI is the rule, but the check is about the mix).
  EXPECT_NO_THROW(read_scene_mesh(scene("bar_mm.msh", 1000.0)));
}

TEST_F(SceneMeshUnits, ChecksTheMeshThatMeshReplacesItWith) {
  scenes::Scene bar = scene("bar.msh");
  override_mesh(bar, dir_.path() / "bar_mm.msh");
  EXPECT_THROW(read_scene_mesh(bar), InputError);
}

TEST_F(SceneMeshUnits, RejectsAFixedPlaneFarOffTheMesh) {
  scenes::Scene bar = scene("bar.msh");
  bar.grasp.reset();
  bar.fixed.box.reset();
  bar.fixed.plane = scenes::Plane{Eigen::Vector3d(-50.0, 0.0, 0.0), Eigen::Vector3d::UnitX(), 1.0};
  EXPECT_THROW(read_scene_mesh(bar), InputError);
  // Through the bar, wherever its point lies on it: nothing to judge the size by.
  bar.fixed.plane = scenes::Plane{Eigen::Vector3d(0.0, 40.0, 9.0), Eigen::Vector3d::UnitX(), 0.0};
  EXPECT_NO_THROW(read_scene_mesh(bar));
}

TEST_F(SceneMeshUnits, LeavesAlonePlacesItCannotJudgeAVertexListOnly) {
  // SOFA's liver in its raw units (scenes/sofa_liver.json) is fixed by vertex indices alone.
  scenes::Scene bar = scene("bar_mm.msh");
  bar.grasp.reset();
  bar.fixed.box.reset();
  bar.fixed.vertices = {0, 1};
  EXPECT_NO_THROW(read_scene_mesh(bar));
}

}  // namespace
}  // namespace softbench::harness
