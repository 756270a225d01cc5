// SPDX-License-Identifier: MIT
// Scene files: what a valid one becomes, the defaults filled in, the echo through to_json, and
// the exact message for each kind of mistake (file, JSON pointer, expected, got).
#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "scenes/scene.h"
#include "tests/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

namespace softbench::scenes {
namespace {

// The smallest valid scene; each test patches it (RFC 7396 merge patch: null removes a key).
constexpr const char* kMinimalScene = R"({
  "name": "box",
  "mesh": "box.msh",
  "material": { "young_modulus": 3000.0, "poisson_ratio": 0.3, "density": 1060.0 },
  "time": { "dt": 0.01, "duration": 1.0 },
  "fixed": { "box": { "min": [0, 0, 0], "max": [0.1, 0.1, 0] } }
})";

// Every key the format has, with non-default values.
constexpr const char* kFullScene = R"({
  // comments are allowed
  "name": "full",
  "description": "every key",
  "mesh": "box.msh",
  "material": { "young_modulus": 5000.0, "poisson_ratio": 0.45, "density": 1000.0 },
  "gravity": { "acceleration": [0.0, -9.81, 0.0], "off_at": 0.75 },
  "time": { "dt": 0.005, "duration": 2.0 },
  "fixed": {
    "vertices": [3, 1],
    "box": { "min": [0, 0, 0], "max": [0.1, 0.1, 0] },
    "plane": { "point": [0, 0, 0], "normal": [2, 0, 0], "tolerance": 0.001 }
  },
  "initial_velocity": { "linear": [0.1, 0, -0.2], "angular": [0, 0, 3], "center": [0.05, 0.05, 0] },
  "grasp": {
    "center": [0.1, 0.1, 0.1],
    "radius": 0.02,
    "start": 0.5,
    "release": 1.5,
    "path": [
      { "t": 0.5, "offset": [0, 0, 0] },
      { "t": 1.0, "offset": [0, 0, 0.03] }
    ]
  },
  "instrument": {
    "mesh": "tool.obj",
    "start": 0.25,
    "release": 1.5,
    "contact_margin": 0.001,
    "contact_passes": 6,
    "path": [
      { "t": 0.0, "position": [0.05, 0.05, 0.2] },
      { "t": 0.5, "position": [0.05, 0.05, 0.1], "rotation": { "axis": [0, 0, 2], "degrees": 90 } },
      { "t": 1.5, "position": [0.05, 0.05, 0.2] }
    ]
  },
  "limits": { "max_speed": 20.0, "max_displacement": 3.0 },
  "requirements": { "steps_per_second": 30, "accuracy": 0.1, "outputs": ["surface", "contact_force"] },
  "models": { "mass_spring": { "stiffness": 180.0, "damping": 5.0 }, "other": {} }
})";

class SceneLoader : public ::testing::Test {
 protected:
  SceneLoader() {
    write_msh(dir_.path() / "box.msh", test::box_tets(2, 2, 2, 0.1, 0.1, 0.1));
    write_obj(dir_.path() / "tool.obj", test::cube_surface());
  }

  // The minimal scene with `patch` merged in, written to scene.json.
  std::filesystem::path write_scene(const std::string& patch = "{}") const {
    nlohmann::json json = nlohmann::json::parse(kMinimalScene);
    json.merge_patch(nlohmann::json::parse(patch));
    return dir_.write("scene.json", json.dump(2));
  }

  Scene load(const std::string& patch = "{}") const { return load_scene(write_scene(patch)); }

  // The message load_scene throws for the minimal scene with `patch` merged in, without the
  // "<file>: " prefix, which it checks.
  std::string error_for(const std::string& patch) const {
    return error_loading(write_scene(patch));
  }

  static std::string error_loading(const std::filesystem::path& file) {
    try {
      load_scene(file);
    } catch (const InputError& error) {
      const std::string message = error.what();
      const std::string prefix = file.string() + ": ";
      EXPECT_EQ(message.substr(0, prefix.size()), prefix);
      return message.substr(std::min(prefix.size(), message.size()));
    }
    ADD_FAILURE() << "no InputError for " << file;
    return {};
  }

  test::TempDir dir_;
};

void expect_same_scene(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.description, b.description);
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.mesh, b.mesh);
  EXPECT_EQ(a.material.young_modulus, b.material.young_modulus);
  EXPECT_EQ(a.material.poisson_ratio, b.material.poisson_ratio);
  EXPECT_EQ(a.material.density, b.material.density);
  EXPECT_EQ(a.gravity.acceleration, b.gravity.acceleration);
  EXPECT_EQ(a.gravity.off_at, b.gravity.off_at);
  EXPECT_EQ(a.dt, b.dt);
  EXPECT_EQ(a.duration, b.duration);
  EXPECT_EQ(a.fixed.vertices, b.fixed.vertices);
  ASSERT_EQ(a.fixed.box.has_value(), b.fixed.box.has_value());
  if (a.fixed.box) {
    EXPECT_EQ(a.fixed.box->min, b.fixed.box->min);
    EXPECT_EQ(a.fixed.box->max, b.fixed.box->max);
  }
  ASSERT_EQ(a.fixed.plane.has_value(), b.fixed.plane.has_value());
  if (a.fixed.plane) {
    EXPECT_EQ(a.fixed.plane->point, b.fixed.plane->point);
    // Normalising a unit vector again may move it by an ulp.
    EXPECT_TRUE(a.fixed.plane->normal.isApprox(b.fixed.plane->normal, 1e-15));
    EXPECT_EQ(a.fixed.plane->tolerance, b.fixed.plane->tolerance);
  }
  ASSERT_EQ(a.initial_velocity.has_value(), b.initial_velocity.has_value());
  if (a.initial_velocity) {
    EXPECT_EQ(a.initial_velocity->linear, b.initial_velocity->linear);
    EXPECT_EQ(a.initial_velocity->angular, b.initial_velocity->angular);
    EXPECT_EQ(a.initial_velocity->center, b.initial_velocity->center);
  }
  ASSERT_EQ(a.grasp.has_value(), b.grasp.has_value());
  if (a.grasp) {
    EXPECT_EQ(a.grasp->center, b.grasp->center);
    EXPECT_EQ(a.grasp->radius, b.grasp->radius);
    EXPECT_EQ(a.grasp->start, b.grasp->start);
    EXPECT_EQ(a.grasp->release, b.grasp->release);
    ASSERT_EQ(a.grasp->path.size(), b.grasp->path.size());
    for (std::size_t i = 0; i < a.grasp->path.size(); ++i) {
      EXPECT_EQ(a.grasp->path[i].time, b.grasp->path[i].time);
      EXPECT_EQ(a.grasp->path[i].offset, b.grasp->path[i].offset);
    }
  }
  ASSERT_EQ(a.instrument.has_value(), b.instrument.has_value());
  if (a.instrument) {
    EXPECT_EQ(a.instrument->mesh, b.instrument->mesh);
    ASSERT_EQ(a.instrument->path.size(), b.instrument->path.size());
    for (std::size_t i = 0; i < a.instrument->path.size(); ++i) {
      EXPECT_EQ(a.instrument->path[i].time, b.instrument->path[i].time);
      EXPECT_EQ(a.instrument->path[i].position, b.instrument->path[i].position);
      EXPECT_TRUE(
          a.instrument->path[i].orientation.isApprox(b.instrument->path[i].orientation, 1e-12));
    }
    EXPECT_EQ(a.instrument->start, b.instrument->start);
    EXPECT_EQ(a.instrument->release, b.instrument->release);
    EXPECT_EQ(a.instrument->contact_margin, b.instrument->contact_margin);
    EXPECT_EQ(a.instrument->contact_passes, b.instrument->contact_passes);
  }
  ASSERT_EQ(a.requirements.has_value(), b.requirements.has_value());
  if (a.requirements) {
    EXPECT_EQ(a.requirements->steps_per_second, b.requirements->steps_per_second);
    EXPECT_EQ(a.requirements->accuracy, b.requirements->accuracy);
    EXPECT_EQ(a.requirements->outputs, b.requirements->outputs);
  }
  EXPECT_EQ(a.limits.max_speed, b.limits.max_speed);
  EXPECT_EQ(a.limits.max_displacement, b.limits.max_displacement);
  EXPECT_EQ(a.model_parameters, b.model_parameters);
}

TEST_F(SceneLoader, LoadsAMinimalSceneWithDefaultsFilledIn) {
  const std::filesystem::path file = write_scene();
  const Scene scene = load_scene(file);
  EXPECT_EQ(scene.name, "box");
  EXPECT_EQ(scene.description, "");
  EXPECT_EQ(scene.source, file);
  EXPECT_EQ(scene.mesh, dir_.path() / "box.msh");
  EXPECT_EQ(scene.material.young_modulus, 3000.0);
  EXPECT_EQ(scene.material.poisson_ratio, 0.3);
  EXPECT_EQ(scene.material.density, 1060.0);
  EXPECT_EQ(scene.gravity.acceleration, Eigen::Vector3d(0.0, 0.0, -9.81));
  EXPECT_EQ(scene.gravity.off_at, kNever);
  EXPECT_EQ(scene.dt, 0.01);
  EXPECT_EQ(scene.duration, 1.0);
  EXPECT_TRUE(scene.fixed.vertices.empty());
  ASSERT_TRUE(scene.fixed.box.has_value());
  EXPECT_EQ(scene.fixed.box->max, Eigen::Vector3d(0.1, 0.1, 0.0));
  EXPECT_FALSE(scene.fixed.plane.has_value());
  EXPECT_FALSE(scene.initial_velocity.has_value());
  EXPECT_FALSE(scene.grasp.has_value());
  EXPECT_FALSE(scene.instrument.has_value());
  EXPECT_EQ(scene.limits.max_speed, 50.0);
  EXPECT_EQ(scene.limits.max_displacement, 10.0);
  EXPECT_TRUE(scene.model_parameters.empty());
}

TEST_F(SceneLoader, DefaultsTheTimeStepToOneSixtiethOfASecond) {
  EXPECT_EQ(load(R"({"time": {"dt": null}})").dt, 1.0 / 60.0);
}

TEST_F(SceneLoader, ReadsEveryKeyOfAFullScene) {
  const Scene scene = load_scene(dir_.write("full.json", kFullScene));
  EXPECT_EQ(scene.description, "every key");
  EXPECT_EQ(scene.material.poisson_ratio, 0.45);
  EXPECT_EQ(scene.gravity.acceleration, Eigen::Vector3d(0.0, -9.81, 0.0));
  EXPECT_EQ(scene.gravity.off_at, 0.75);
  EXPECT_EQ(scene.fixed.vertices, (std::vector<int>{3, 1}));
  ASSERT_TRUE(scene.fixed.plane.has_value());
  EXPECT_EQ(scene.fixed.plane->normal, Eigen::Vector3d::UnitX());  // normalised
  EXPECT_EQ(scene.fixed.plane->tolerance, 0.001);
  ASSERT_TRUE(scene.initial_velocity.has_value());
  EXPECT_EQ(scene.initial_velocity->linear, Eigen::Vector3d(0.1, 0.0, -0.2));
  EXPECT_EQ(scene.initial_velocity->angular, Eigen::Vector3d(0.0, 0.0, 3.0));
  EXPECT_EQ(scene.initial_velocity->center, Eigen::Vector3d(0.05, 0.05, 0.0));
  ASSERT_TRUE(scene.grasp.has_value());
  EXPECT_EQ(scene.grasp->radius, 0.02);
  EXPECT_EQ(scene.grasp->start, 0.5);
  EXPECT_EQ(scene.grasp->release, 1.5);
  ASSERT_EQ(scene.grasp->path.size(), 2u);
  EXPECT_EQ(scene.grasp->path[1].time, 1.0);
  EXPECT_EQ(scene.grasp->path[1].offset, Eigen::Vector3d(0.0, 0.0, 0.03));
  ASSERT_TRUE(scene.instrument.has_value());
  EXPECT_EQ(scene.instrument->mesh, dir_.path() / "tool.obj");
  ASSERT_EQ(scene.instrument->path.size(), 3u);
  EXPECT_EQ(scene.instrument->path[0].position, Eigen::Vector3d(0.05, 0.05, 0.2));
  // The axis is normalised; 90 degrees about z takes x to y.
  EXPECT_TRUE((scene.instrument->path[1].orientation * Eigen::Vector3d::UnitX())
                  .isApprox(Eigen::Vector3d::UnitY(), 1e-15));
  EXPECT_EQ(scene.instrument->start, 0.25);
  EXPECT_EQ(scene.instrument->release, 1.5);
  EXPECT_EQ(scene.instrument->contact_margin, 0.001);
  EXPECT_EQ(scene.instrument->contact_passes, 6);
  EXPECT_EQ(scene.limits.max_speed, 20.0);
  EXPECT_EQ(scene.limits.max_displacement, 3.0);
  ASSERT_EQ(scene.model_parameters.size(), 2u);
  EXPECT_EQ(scene.model_parameters.at("mass_spring")["stiffness"], 180.0);
  EXPECT_TRUE(scene.model_parameters.at("other").empty());
}

TEST_F(SceneLoader, AcceptsGravityAsAPlainVector) {
  const Scene scene = load(R"({"gravity": [0, 0, -1.62]})");
  EXPECT_EQ(scene.gravity.acceleration, Eigen::Vector3d(0.0, 0.0, -1.62));
  EXPECT_EQ(scene.gravity.off_at, kNever);
}

TEST_F(SceneLoader, DefaultsGravityAccelerationInTheObjectForm) {
  const Scene scene = load(R"({"gravity": {"off_at": 0.5}})");
  EXPECT_EQ(scene.gravity.acceleration, Eigen::Vector3d(0.0, 0.0, -9.81));
  EXPECT_EQ(scene.gravity.off_at, 0.5);
}

TEST_F(SceneLoader, ResolvesPathsAgainstTheSceneFilesFolder) {
  std::filesystem::create_directories(dir_.path() / "scenes");
  const std::filesystem::path file = dir_.write("scenes/nested.json", R"({
    "name": "nested",
    "mesh": "../box.msh",
    "material": { "young_modulus": 3000.0, "poisson_ratio": 0.3, "density": 1060.0 },
    "time": { "duration": 1.0 },
    "fixed": { "vertices": [0] }
  })");
  const Scene scene = load_scene(file);
  EXPECT_EQ(scene.mesh, dir_.path() / "box.msh");
  EXPECT_EQ(to_json(scene)["mesh"], "../box.msh");
  expect_same_scene(parse_scene(to_json(scene), file), scene);
}

TEST_F(SceneLoader, EchoesTheEffectiveSceneWithDefaults) {
  const nlohmann::json json = to_json(load());
  EXPECT_EQ(json["mesh"], "box.msh");
  EXPECT_EQ(json["description"], "");
  EXPECT_EQ(json["gravity"], nlohmann::json::parse(R"({"acceleration": [0.0, 0.0, -9.81]})"));
  EXPECT_EQ(json["limits"],
            nlohmann::json::parse(R"({"max_speed": 50.0, "max_displacement": 10.0})"));
  EXPECT_EQ(json["fixed"]["vertices"], nlohmann::json::array());
  EXPECT_EQ(json["models"], nlohmann::json::object());
  EXPECT_FALSE(json.contains("initial_velocity"));  // absent, as the scene wrote it
  EXPECT_FALSE(json.contains("grasp"));
  EXPECT_FALSE(json.contains("instrument"));
}

TEST_F(SceneLoader, AcceptsAFreeBodyWithoutAFixedRegion) {
  for (const char* patch : {R"({"fixed": null})", R"({"fixed": {"box": null}})",
                            R"({"fixed": {"box": null, "vertices": []}})"}) {
    const Scene scene = load(patch);
    EXPECT_TRUE(scene.fixed.vertices.empty()) << patch;
    EXPECT_FALSE(scene.fixed.box.has_value()) << patch;
    EXPECT_FALSE(scene.fixed.plane.has_value()) << patch;
    EXPECT_EQ(to_json(scene)["fixed"], nlohmann::json::parse(R"({"vertices": []})")) << patch;
    expect_same_scene(parse_scene(to_json(scene), scene.source), scene);
  }
}

TEST_F(SceneLoader, ReadsAnInitialVelocityWithItsDefaults) {
  const Scene scene = load(R"({"initial_velocity": {"angular": [0, 0, 3]}})");
  ASSERT_TRUE(scene.initial_velocity.has_value());
  EXPECT_EQ(scene.initial_velocity->linear, Eigen::Vector3d::Zero());
  EXPECT_EQ(scene.initial_velocity->angular, Eigen::Vector3d(0.0, 0.0, 3.0));
  EXPECT_FALSE(scene.initial_velocity->center.has_value());  // the centre of mass, with the mesh
  const nlohmann::json json = to_json(scene);
  EXPECT_EQ(json["initial_velocity"],
            nlohmann::json::parse(R"({"linear": [0.0, 0.0, 0.0], "angular": [0.0, 0.0, 3.0]})"));
  expect_same_scene(parse_scene(json, scene.source), scene);
  EXPECT_EQ(load(R"({"initial_velocity": {"linear": [1, 2, 3]}})").initial_velocity->angular,
            Eigen::Vector3d::Zero());
}

TEST_F(SceneLoader, RejectsAnInitialVelocityWithNeitherLinearNorAngular) {
  EXPECT_EQ(error_for(R"({"initial_velocity": {"center": [0, 0, 0]}})"),
            "/initial_velocity: expected at least one of \"linear\", \"angular\", got "
            "{\"center\":[0,0,0]}");
}

TEST_F(SceneLoader, RejectsAnUnknownKeyInTheInitialVelocity) {
  EXPECT_EQ(error_for(R"({"initial_velocity": {"omega": [0, 0, 3]}})"),
            "/initial_velocity/omega: unknown key (known here: angular, center, linear)");
}

TEST_F(SceneLoader, RejectsAnInitialAngularVelocityThatIsNotAVector) {
  EXPECT_EQ(error_for(R"({"initial_velocity": {"angular": [0, 3]}})"),
            "/initial_velocity/angular: expected [x, y, z] (three finite numbers), got [0,3]");
  EXPECT_EQ(error_for(R"({"initial_velocity": [0, 0, 3]})"),
            "/initial_velocity: expected an object, got [0,0,3]");
}

TEST_F(SceneLoader, RoundTripsAFullSceneThroughToJson) {
  const std::filesystem::path file = dir_.write("full.json", kFullScene);
  const Scene scene = load_scene(file);
  expect_same_scene(parse_scene(to_json(scene), file), scene);
  // Also through text, as metrics.json stores it.
  expect_same_scene(parse_scene(nlohmann::json::parse(to_json(scene).dump()), file), scene);
}

TEST_F(SceneLoader, RoundTripsAMinimalSceneThroughToJson) {
  const Scene scene = load();
  expect_same_scene(parse_scene(to_json(scene), scene.source), scene);
}

TEST_F(SceneLoader, RejectsPoissonRatioAtOneHalf) {
  EXPECT_EQ(error_for(R"({"material": {"poisson_ratio": 0.5}})"),
            "/material/poisson_ratio: expected a number in [0, 0.5), got 0.5");
}

TEST_F(SceneLoader, RejectsNegativeYoungModulus) {
  EXPECT_EQ(error_for(R"({"material": {"young_modulus": -3000}})"),
            "/material/young_modulus: expected a positive number (Pa), got -3000");
}

TEST_F(SceneLoader, ReadsSupportsAndWritesThemBack) {
  const Scene scene = load(R"({"supports": [{"point": [0, 0, 0], "normal": [0, 0, 2]},
                                            {"point": [0.1, 0, 0], "normal": [1, 0, 0],
                                             "tolerance": 0.001}]})");
  ASSERT_EQ(scene.supports.size(), 2u);
  EXPECT_EQ(scene.supports[0].normal, Eigen::Vector3d(0, 0, 1));  // made unit
  EXPECT_EQ(scene.supports[1].tolerance, 0.001);
  EXPECT_EQ(to_json(scene)["supports"].size(), 2u);
  EXPECT_EQ(error_for(R"({"supports": [{"point": [0, 0, 0], "normal": [0, 0, 0]}]})"),
            "/supports/0/normal: expected a non-zero [x, y, z], got [0,0,0]");
}

TEST_F(SceneLoader, RejectsAnUnknownTopLevelKey) {
  EXPECT_EQ(error_for(R"({"gravty": [0, 0, -9.81]})"),
            "/gravty: unknown key (known here: description, fixed, grasp, gravity, "
            "initial_velocity, instrument, limits, material, mesh, models, name, requirements, "
            "supports, time)");
}

TEST_F(SceneLoader, RejectsAnUnknownNestedKey) {
  EXPECT_EQ(error_for(R"({"time": {"dtt": 0.01}})"),
            "/time/dtt: unknown key (known here: dt, duration)");
}

TEST_F(SceneLoader, RejectsAnUnknownKeyInAKeyframe) {
  EXPECT_EQ(
      error_for(R"({"grasp": {"center": [0, 0, 0], "path": [{"t": 0, "ofset": [0, 0, 0]}]}})"),
      "/grasp/path/0/ofset: unknown key (known here: offset, t)");
}

// Found by fuzz_scene: a key holding a line break ("instrume\nt") put the break in the message,
// which the CLI must print on one line.
TEST_F(SceneLoader, NamesAKeyWithALineBreakOnOneLine) {
  EXPECT_EQ(error_for(R"({"instrume\nt": {}})"),
            "/instrume\\nt: unknown key (known here: description, fixed, grasp, gravity, "
            "initial_velocity, instrument, limits, material, mesh, models, name, requirements, "
            "supports, time)");
  EXPECT_EQ(error_for(R"({"mesh": "data/a\nb.msh"})"),
            "/mesh: file not found: " + (dir_.path() / "data").string() + "/a\\nb.msh");
}

TEST_F(SceneLoader, RejectsAMissingMeshFile) {
  EXPECT_EQ(error_for(R"({"mesh": "data/missing.msh"})"),
            "/mesh: file not found: " + (dir_.path() / "data/missing.msh").string());
}

TEST_F(SceneLoader, RejectsAMissingInstrumentMeshFile) {
  EXPECT_EQ(error_for(R"({"instrument": {"mesh": "probe.obj", "path": []}})"),
            "/instrument/mesh: file not found: " + (dir_.path() / "probe.obj").string());
}

TEST_F(SceneLoader, RejectsAMissingRequiredKey) {
  EXPECT_EQ(error_for(R"({"material": {"density": null}})"),
            "/material/density: missing (required)");
  EXPECT_EQ(error_for(R"({"time": null})"), "/time: missing (required)");
  EXPECT_EQ(error_for(R"({"name": null})"), "/name: missing (required)");
}

TEST_F(SceneLoader, RejectsAStringWhereANumberIsExpected) {
  EXPECT_EQ(error_for(R"({"material": {"density": "1060"}})"),
            "/material/density: expected a finite number, got \"1060\"");
}

TEST_F(SceneLoader, RejectsANumberWhereAnObjectIsExpected) {
  EXPECT_EQ(error_for(R"({"time": 1.0})"), "/time: expected an object, got 1.0");
}

TEST_F(SceneLoader, RejectsAVectorWithTwoComponents) {
  EXPECT_EQ(error_for(R"({"gravity": [0, -9.81]})"),
            "/gravity: expected [x, y, z] (three finite numbers), got [0,-9.81]");
}

TEST_F(SceneLoader, RejectsGravityThatIsNeitherAVectorNorAnObject) {
  EXPECT_EQ(error_for(R"({"gravity": "down"})"),
            "/gravity: expected [x, y, z] or {\"acceleration\": [x, y, z], \"off_at\": t}, got "
            "\"down\"");
}

TEST_F(SceneLoader, RejectsANegativeTime) {
  EXPECT_EQ(error_for(R"({"gravity": {"off_at": -1}})"),
            "/gravity/off_at: expected a number >= 0, got -1");
}

TEST_F(SceneLoader, RejectsATimeStepLongerThanTheDuration) {
  EXPECT_EQ(error_for(R"({"time": {"dt": 2.0}})"),
            "/time/dt: expected a number <= duration (1), got 2.0");
}

TEST_F(SceneLoader, RejectsAZeroDuration) {
  EXPECT_EQ(error_for(R"({"time": {"duration": 0}})"),
            "/time/duration: expected a number > 0, got 0");
}

TEST_F(SceneLoader, RejectsGraspKeyframesOutOfOrder) {
  EXPECT_EQ(error_for(R"({"grasp": {"center": [0, 0, 0], "start": 1, "path": [
                {"t": 1.0, "offset": [0, 0, 0]},
                {"t": 1.5, "offset": [0, 0, 0.01]},
                {"t": 1.2, "offset": [0, 0, 0.02]}]}})"),
            "/grasp/path/2/t: expected a number > 1.5 (the previous keyframe's t), got 1.2");
}

TEST_F(SceneLoader, RejectsAGraspKeyframeAfterTheRelease) {
  EXPECT_EQ(error_for(R"({"grasp": {"center": [0, 0, 0], "start": 1, "release": 2, "path": [
                {"t": 1.0, "offset": [0, 0, 0]},
                {"t": 2.5, "offset": [0, 0, 0.01]}]}})"),
            "/grasp/path/1/t: expected a number in [start, release] = [1, 2], got 2.5");
}

TEST_F(SceneLoader, RejectsAGraspKeyframeBeforeTheStart) {
  EXPECT_EQ(error_for(R"({"grasp": {"center": [0, 0, 0], "start": 1,
                "path": [{"t": 0.5, "offset": [0, 0, 0]}]}})"),
            "/grasp/path/0/t: expected a number >= start (1), got 0.5");
}

TEST_F(SceneLoader, RejectsAGraspReleasedBeforeItStarts) {
  EXPECT_EQ(error_for(R"({"grasp": {"center": [0, 0, 0], "start": 1, "release": 1}})"),
            "/grasp/release: expected a number > start (1), got 1");
}

TEST_F(SceneLoader, RejectsAZeroGraspRadius) {
  EXPECT_EQ(error_for(R"({"grasp": {"center": [0, 0, 0], "radius": 0}})"),
            "/grasp/radius: expected a number > 0, got 0");
}

TEST_F(SceneLoader, RejectsABoxWithMinAboveMax) {
  EXPECT_EQ(error_for(R"({"fixed": {"box": {"min": [0, 0, 0.2]}}})"),
            "/fixed/box/max: expected [x, y, z] >= min [0, 0, 0.2] in every coordinate, got "
            "[0.1,0.1,0]");
}

TEST_F(SceneLoader, RejectsAZeroPlaneNormal) {
  EXPECT_EQ(error_for(R"({"fixed": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 0]}}})"),
            "/fixed/plane/normal: expected a non-zero [x, y, z], got [0,0,0]");
}

TEST_F(SceneLoader, RejectsANegativePlaneTolerance) {
  EXPECT_EQ(error_for(R"({"fixed": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1],
                "tolerance": -0.01}}})"),
            "/fixed/plane/tolerance: expected a number >= 0, got -0.01");
}

TEST_F(SceneLoader, RejectsANegativeFixedVertexIndex) {
  EXPECT_EQ(error_for(R"({"fixed": {"vertices": [0, -1]}})"),
            "/fixed/vertices/1: expected an integer in [0, 2147483647], got -1");
}

TEST_F(SceneLoader, ReadsRequirementsWithTheirDefaults) {
  const Scene scene = load(R"({"requirements": {"steps_per_second": 60, "accuracy": 0.05}})");
  ASSERT_TRUE(scene.requirements.has_value());
  EXPECT_EQ(scene.requirements->steps_per_second, 60.0);
  EXPECT_EQ(scene.requirements->accuracy, 0.05);
  EXPECT_EQ(scene.requirements->outputs, std::vector<std::string>{"surface"});
  EXPECT_FALSE(load("{}").requirements.has_value());
}

TEST_F(SceneLoader, RejectsAnUnknownRequiredOutput) {
  EXPECT_EQ(error_for(R"({"requirements": {"outputs": ["surface", "colour"]}})"),
            "/requirements/outputs: expected a non-empty array of \"surface\", \"volume\", "
            "\"contact_force\", got [\"surface\",\"colour\"]");
}

TEST_F(SceneLoader, RejectsAnInstrumentKeyframeWithoutAPosition) {
  EXPECT_EQ(error_for(R"({"instrument": {"mesh": "tool.obj", "path": [{"t": 0}]}})"),
            "/instrument/path/0/position: missing (required)");
}

TEST_F(SceneLoader, RejectsInstrumentKeyframesOutOfOrder) {
  EXPECT_EQ(error_for(R"({"instrument": {"mesh": "tool.obj", "path": [
                {"t": 1, "position": [0, 0, 1]}, {"t": 1, "position": [0, 0, 0]}]}})"),
            "/instrument/path/1/t: expected a number > 1 (the previous keyframe's t), got 1");
}

TEST_F(SceneLoader, RejectsInstrumentContactPassesOutsideOneToAThousand) {
  EXPECT_EQ(error_for(R"({"instrument": {"mesh": "tool.obj", "contact_passes": 0,
                "path": [{"t": 0, "position": [0, 0, 1]}]}})"),
            "/instrument/contact_passes: expected an integer in [1, 1000], got 0");
  EXPECT_EQ(error_for(R"({"instrument": {"mesh": "tool.obj", "contact_passes": 2.5,
                "path": [{"t": 0, "position": [0, 0, 1]}]}})"),
            "/instrument/contact_passes: expected an integer in [1, 1000], got 2.5");
}

TEST_F(SceneLoader, RejectsAZeroRotationAxis) {
  EXPECT_EQ(error_for(R"({"instrument": {"mesh": "tool.obj", "path": [
                {"t": 0, "position": [0, 0, 1], "rotation": {"axis": [0, 0, 0], "degrees": 5}}]}})"),
            "/instrument/path/0/rotation/axis: expected a non-zero vector, got [0,0,0]");
}

TEST_F(SceneLoader, ARotationAxisOfAnyFiniteLengthIsItsDirection) {
  // 1e200 squared overflows and 1e-200 squared underflows: a naive norm made the first the
  // identity rotation and the second a "zero" axis.
  for (const char* axis : {"[0, 0, 1e200]", "[0, 0, 1e-200]"}) {
    const Scene scene = load(std::string(R"({"instrument": {"mesh": "tool.obj", "path": [
                {"t": 0, "position": [0, 0, 1], "rotation": {"axis": )")
                             + axis + R"(, "degrees": 90}}]}})");
    EXPECT_TRUE((scene.instrument->path[0].orientation * Eigen::Vector3d::UnitX())
                    .isApprox(Eigen::Vector3d::UnitY(), 1e-15))
        << axis;
  }
}

// Found by fuzz_scene: 1e308 degrees times pi overflowed to an infinite angle; the scene loaded
// with a NaN orientation, and its echo did not load.
TEST_F(SceneLoader, ARotationOfAnyFiniteDegreesIsAFiniteRotation) {
  const double whole_turns = std::ldexp(360.0, 1015);  // 1.26e308, a multiple of 360 exactly
  for (const double degrees : {whole_turns, -whole_turns}) {
    std::ostringstream patch;
    patch.precision(17);
    patch << R"({"instrument": {"mesh": "tool.obj", "path": [
                {"t": 0, "position": [0, 0, 1], "rotation": {"axis": [0, 0, 1], "degrees": )"
          << degrees << "}}]}}";
    const Scene scene = load(patch.str());
    EXPECT_TRUE((scene.instrument->path[0].orientation * Eigen::Vector3d::UnitX())
                    .isApprox(Eigen::Vector3d::UnitX(), 1e-15))
        << degrees;
    expect_same_scene(parse_scene(to_json(scene), scene.source), scene);
  }
}

TEST_F(SceneLoader, RejectsAnInstrumentReleasedBeforeItStarts) {
  EXPECT_EQ(error_for(R"({"instrument": {"mesh": "tool.obj", "start": 2, "release": 1,
                "path": [{"t": 0, "position": [0, 0, 1]}]}})"),
            "/instrument/release: expected a time > start (2), got 1");
}

TEST_F(SceneLoader, RejectsTwoReleasesForAGraspingInstrument) {
  EXPECT_EQ(error_for(R"({"instrument": {"mesh": "tool.obj", "release": 3,
                "grasp": {"center": [0, 0, 0], "start": 1, "release": 2},
                "path": [{"t": 0, "position": [0, 0, 1]}]}})"),
            "/instrument/release: an instrument with a grasp is released by "
            "/instrument/grasp/release");
}

TEST_F(SceneLoader, AGraspingInstrumentIsReleasedWithItsGrasp) {
  const Scene scene = load(R"({"instrument": {"mesh": "tool.obj", "start": 0.5,
      "grasp": {"center": [0, 0, 0], "radius": 0.01, "start": 1, "release": 2}, "path": [{"t": 0, "position": [0, 0, 1]}]}})");
  ASSERT_TRUE(scene.instrument && scene.instrument->grasp);
  EXPECT_EQ(scene.release_time(), 2.0);
  EXPECT_EQ(scene.reference_time(), 0.5);
}

TEST_F(SceneLoader, RejectsASceneGraspBesideAGraspingInstrument) {
  EXPECT_EQ(error_for(R"({"grasp": {"center": [0, 0, 0]},
      "instrument": {"mesh": "tool.obj", "grasp": {"center": [0, 0, 0], "start": 1, "release": 2},
                     "path": [{"t": 0, "position": [0, 0, 1]}]}})"),
            "/grasp: a scene grasp and an instrument grasp together; keep one");
}

TEST_F(SceneLoader, RejectsAnEmptyInstrumentPath) {
  EXPECT_EQ(error_for(R"({"instrument": {"mesh": "tool.obj", "path": []}})"),
            "/instrument/path: expected at least one keyframe, got []");
}

TEST_F(SceneLoader, RejectsAModelBlockThatIsNotAnObject) {
  EXPECT_EQ(error_for(R"({"models": {"mass_spring": 180}})"),
            "/models/mass_spring: expected an object (the model's parameters), got 180");
}

TEST_F(SceneLoader, RejectsANonPositiveStabilityLimit) {
  EXPECT_EQ(error_for(R"({"limits": {"max_speed": 0}})"),
            "/limits/max_speed: expected a number > 0, got 0");
}

TEST_F(SceneLoader, RejectsAnEmptyName) {
  EXPECT_EQ(error_for(R"({"name": ""})"), "/name: expected a non-empty string, got \"\"");
}

TEST_F(SceneLoader, RejectsInvalidJsonNamingTheFileAndLine) {
  const std::filesystem::path file = dir_.write("broken.json", "{\n  \"name\": \"x\",\n  }\n");
  EXPECT_EQ(error_loading(file),
            "invalid JSON: parse error at line 3, column 3: syntax error while parsing object key "
            "- unexpected '}'; expected string literal");
}

TEST_F(SceneLoader, RejectsARootThatIsNotAnObject) {
  EXPECT_EQ(error_loading(dir_.write("array.json", "[1, 2]")), "/: expected an object, got [1,2]");
}

TEST_F(SceneLoader, RejectsAMissingSceneFile) {
  const std::filesystem::path file = dir_.path() / "absent.json";
  EXPECT_EQ(error_loading(file), "no such file");
}

TEST_F(SceneLoader, RejectsAFolderGivenAsTheSceneFile) {
  EXPECT_EQ(error_loading(dir_.path()), "is a folder, not a scene file");
}

// 100,000 levels would overflow the stack in nlohmann's recursive dump and destruction (exit
// 139); the parse stops at kMaxJsonDepth instead.
TEST_F(SceneLoader, RejectsAValueNestedDeeperThanTheLimit) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_EQ(error_loading(dir_.write("deep.json", R"({"name": "x", "description": )" + deep + "}")),
            "/description: nested deeper than 64 levels of arrays and objects (the limit)");
  const std::string deep_object = [] {
    std::string text;
    for (int i = 0; i < 100000; ++i) {
      text += R"({"a": )";
    }
    return text + "1" + std::string(100000, '}');
  }();
  EXPECT_EQ(error_loading(dir_.write("deep_model.json",
                                     R"({"models": {"mass_spring": )" + deep_object + "}}")),
            "/models: nested deeper than 64 levels of arrays and objects (the limit)");
}

TEST_F(SceneLoader, RejectsANumberBeyondADoubleNamingTheLine) {
  const std::filesystem::path file = dir_.write(
      "huge.json", "{\n  \"name\": \"x\",\n  \"time\": {\"duration\": 1e400}\n}\n");
  EXPECT_EQ(error_loading(file),
            "invalid JSON: number out of range at line 3, column 24: 1e400 (beyond a double)");
}

// The step count is checked before anything is sized by it: these gave bad_alloc.
TEST_F(SceneLoader, RejectsMoreTimeStepsThanTheLimit) {
  EXPECT_EQ(error_for(R"({"time": {"dt": 1e-300, "duration": 1.0}})"),
            "/time/duration: 1 s at dt = 1e-300 s is 1e+300 steps, over the limit of 10000000 "
            "(shorten duration or raise dt)");
  EXPECT_EQ(error_for(R"({"time": {"dt": null, "duration": 1e9}})"),
            "/time/duration: 1e+09 s at dt = 0.0166667 s is 6e+10 steps, over the limit of "
            "10000000 (shorten duration or raise dt)");
  EXPECT_EQ(load(R"({"time": {"dt": 0.01, "duration": 100000.0}})").num_steps(), kMaxSteps);
}

TEST(Scene, CountsStepsRoundingUpOnlyBeyondFloatingPointNoise) {
  Scene scene;
  scene.dt = 0.016666666666666666;  // 1/60, as a scene file writes it
  scene.duration = 3.5;
  EXPECT_EQ(scene.num_steps(), 210);
  scene.duration = 0.1;
  scene.dt = 0.03;
  EXPECT_EQ(scene.num_steps(), 4);
  scene.dt = 0.1;
  EXPECT_EQ(scene.num_steps(), 1);
}

TEST(Scene, MeasuresRecoveryFromTheGraspOrElseFromGravity) {
  Scene scene;
  EXPECT_EQ(scene.release_time(), kNever);
  EXPECT_EQ(scene.reference_time(), 0.0);
  scene.gravity.off_at = 1.5;
  EXPECT_EQ(scene.release_time(), 1.5);
  EXPECT_EQ(scene.reference_time(), 0.0);
  scene.grasp = Grasp{};
  scene.grasp->start = 1.0;
  scene.grasp->release = 2.0;
  EXPECT_EQ(scene.release_time(), 2.0);
  EXPECT_EQ(scene.reference_time(), 1.0);
}

TEST(Scene, MeasuresRecoveryFromTheInstrumentsStartAndRelease) {
  Scene scene;
  scene.instrument = Instrument{};
  scene.instrument->start = 0.5;
  scene.instrument->release = 1.5;
  EXPECT_EQ(scene.reference_time(), 0.5);
  EXPECT_EQ(scene.release_time(), 1.5);
}

}  // namespace
}  // namespace softbench::scenes
