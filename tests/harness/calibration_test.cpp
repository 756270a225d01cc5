// SPDX-License-Identifier: MIT
// Calibration (harness/calibrate/): the tissue response it matches, the fit, its record and
// cache, and what it refuses.
#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "harness/calibrate/calibration.h"
#include "harness/calibrate/tissue_response.h"
#include "harness/run/scene_mesh.h"
#include "models/json_file.h"
#include "models/model_registry.h"
#include "scenes/scene.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace softbench::harness {
namespace {

using ::testing::HasSubstr;

// A 10 x 4 x 4 cm bar (E 50 kPa: a 2 cm tip sag as a cantilever) clamped at x = 0 under
// gravity, and a 1 cm cube as the instrument (its frame's origin mid-bottom face, the tip).
class Calibration : public ::testing::Test {
 protected:
  void SetUp() override {
    write_msh(dir_.path() / "bar.msh", test::box_tets(5, 2, 2, 0.1, 0.04, 0.04));
    MeshData cube = test::cube_surface();
    cube.vertices = (0.01 * cube.vertices).colwise() - Eigen::Vector3d(0.005, 0.005, 0.0);
    write_obj(dir_.path() / "cube.obj", cube);
  }

  scenes::Scene scene(const std::string& models, bool instrument = true) const {
    const std::string tool = R"(, "instrument": {"mesh": "cube.obj", "path": [
        {"t": 0, "position": [0.06, 0.02, 0.1]}]})";
    return scenes::load_scene(dir_.write("bar.json", R"({
      "name": "bar",
      "mesh": "bar.msh",
      "material": {"young_modulus": 50000, "poisson_ratio": 0.3, "density": 1060},
      "gravity": [0, 0, -9.81],
      "time": {"dt": 0.016666666666666666, "duration": 1.0},
      "fixed": {"box": {"min": [-0.001, -1, -1], "max": [0.001, 1, 1]}})"
                                                     + (instrument ? tool : std::string())
                                                     + R"(, "models": )" + models + "}"));
  }

  CalibrationOptions options(const std::string& against) const {
    CalibrationOptions result;
    result.against = against;
    result.cache_dir = dir_.path() / "cache";
    return result;
  }

  test::TempDir dir_;
};

TEST_F(Calibration, TheResponseIsASagAndARisingPressForce) {
  const scenes::Scene bar = scene(R"({"corotational_fem": {"rayleigh_mass": 5}})");
  const SceneMesh mesh = read_scene_mesh(bar);
  const TissueResponse response = tissue_response(bar, mesh, "corotational_fem",
                                                  bar.parameters_for("corotational_fem"));
  EXPECT_TRUE(response.sag.settled);
  // Mean sag of the free vertices: a few millimetres for a 2 cm tip deflection.
  EXPECT_GT(response.sag.sag, 0.002);
  EXPECT_LT(response.sag.sag, 0.02);
  ASSERT_EQ(response.forces.size(), 3u);
  EXPECT_GT(response.forces[0], 0.0);
  EXPECT_LT(response.forces[0], response.forces[1]);
  EXPECT_LT(response.forces[1], response.forces[2]);
}

TEST_F(Calibration, ACrumpledBodyIsNotATissuesResponse) {
  // Springs a ten-thousandth as stiff as the bar's material: it folds under its own weight.
  const scenes::Scene bar = scene(R"({"mass_spring": {"stiffness_scale": 1e-4, "mass_damping": 5},
                                      "corotational_fem": {"rayleigh_mass": 5}})");
  const SceneMesh mesh = read_scene_mesh(bar);
  const TissueResponse rag =
      tissue_response(bar, mesh, "mass_spring", bar.parameters_for("mass_spring"));
  EXPECT_THAT(rag.implausible, HasSubstr("under gravity: "));
  EXPECT_FALSE(rag.sag.implausible.empty());
  EXPECT_FALSE(rag.sag.settled);
  // Not pressed: a crumpled body's forces are not a tissue's.
  for (double force : rag.forces) {
    EXPECT_TRUE(std::isnan(force));
  }
  const TissueResponse tissue = tissue_response(bar, mesh, "corotational_fem",
                                                bar.parameters_for("corotational_fem"));
  EXPECT_EQ(tissue.implausible, "");
}

TEST_F(Calibration, MassSpringRecoversTheStiffnessScaleItWasRunWith) {
  constexpr double kScale = 2.0;
  const scenes::Scene bar =
      scene(R"({"mass_spring": {"stiffness_scale": 2.0, "mass_damping": 5}})");
  const SceneMesh mesh = read_scene_mesh(bar);
  const harness::Calibration fit = calibrate(bar, mesh, "mass_spring", options("mass_spring"));
  EXPECT_NEAR(fit.values["stiffness_scale"].get<double>() / kScale, 1.0, 0.02);
  // The same model at the same scale: every target matches to within the fit's resolution.
  for (double error : fit.errors) {
    EXPECT_LT(std::abs(error), 0.02);
  }
  EXPECT_LE(fit.evaluations, 25);
}

TEST_F(Calibration, RecordsWhatItWasFittedToAndIsReadFromTheCacheTheSecondTime) {
  const scenes::Scene bar = scene(R"({"corotational_fem": {"rayleigh_mass": 5}})");
  const SceneMesh mesh = read_scene_mesh(bar);
  const harness::Calibration first =
      calibrate(bar, mesh, "shape_matching", options("corotational_fem"));
  EXPECT_FALSE(first.cached);
  const nlohmann::json& record = first.params["calibrated"];
  EXPECT_EQ(record["against"], "corotational_fem");
  EXPECT_EQ(record["dt"], bar.dt);
  EXPECT_EQ(record["sag"], first.reference.sag.sag);
  EXPECT_EQ(record["forces"].size(), 3u);
  EXPECT_EQ(record["errors"].size(), 4u);
  // The block is one the model reads back as it is.
  EXPECT_EQ(builtin_models()
                .at("shape_matching")
                .create(mesh.body, bar.material, first.params, {})
                ->parameters(),
            first.params);

  const harness::Calibration second =
      calibrate(bar, mesh, "shape_matching", options("corotational_fem"));
  EXPECT_TRUE(second.cached);
  EXPECT_EQ(second.params, first.params);
  EXPECT_EQ(second.errors, first.errors);
}

TEST_F(Calibration, BulletTakesTheReferencesDampingPerStep) {
  if (!builtin_models().contains("bullet_softbody")) {
    GTEST_SKIP() << "built without Bullet";
  }
  const scenes::Scene bar = scene(R"({"corotational_fem": {"rayleigh_mass": 5}})");
  const harness::Calibration fit =
      calibrate(bar, read_scene_mesh(bar), "bullet_softbody", options("corotational_fem"));
  // kDP removes a fraction per step: what a drag of 5 /s removes in one dt.
  EXPECT_NEAR(fit.params["damping"].get<double>(), 1.0 - std::exp(-5.0 * bar.dt), 1e-12);
  EXPECT_TRUE(std::isfinite(fit.objective));
  EXPECT_GT(fit.values["stiffness"].get<double>(), 0.0);
}

TEST_F(Calibration, RefusesAModelThatFollowsTheMaterialAndASceneWithoutInstrument) {
  const scenes::Scene bar = scene("{}");
  const SceneMesh mesh = read_scene_mesh(bar);
  EXPECT_THAT([&] { calibrate(bar, mesh, "corotational_fem", options("neo_hookean")); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("follows the material")));
  const scenes::Scene bare = scene("{}", false);
  EXPECT_THAT([&] { calibrate(bare, read_scene_mesh(bare), "shape_matching", options("corotational_fem")); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("/instrument")));
}

TEST_F(Calibration, TheWrittenSceneFindsItsMeshFromAnotherFolder) {
  const std::filesystem::path file = dir_.path() / "bar.json";
  scene("{}");
  std::filesystem::create_directories(dir_.path() / "elsewhere");
  const nlohmann::json written =
      scene_with_block(read_json_file(file), file, dir_.path() / "elsewhere", "shape_matching",
                       {{"alpha", 0.5}});
  EXPECT_EQ(written["mesh"], "../bar.msh");
  EXPECT_EQ(written["instrument"]["mesh"], "../cube.obj");
  EXPECT_EQ(written["models"]["shape_matching"]["alpha"], 0.5);
}

}  // namespace
}  // namespace softbench::harness
