// SPDX-License-Identifier: MIT
// softbench verify's cases, each on one or two models, with a deliberately wrong setting where a
// pass alone would prove nothing (a case that cannot fail checks nothing), and its reports.
#include "harness/verify/verify.h"

#include "geometry/input_error.h"
#include "geometry/mesh_validation.h"
#include "geometry/shape_meshes.h"
#include "harness/report/verify_report.h"
#include "harness/verify/verify_tolerances.h"
#include "models/model_registry.h"
#include "tests/test_meshes.h"

#include <Eigen/Geometry>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace softbench::harness {
namespace {

using ::testing::HasSubstr;

const Measure& measure(const CaseResult& result, const std::string& name) {
  for (const Measure& m : result.measures) {
    if (m.name == name) {
      return m;
    }
  }
  throw std::logic_error(result.name + " has no measure " + name);
}

std::string describe(const CaseResult& result) {
  std::ostringstream out;
  out << result.name << " " << to_string(result.status) << " (" << result.note << "):";
  for (const Measure& m : result.measures) {
    out << " " << m.name << "=" << m.value;
  }
  return out.str();
}

const ModelUnderTest kFem{"corotational_fem"};

/// `settings` without the command's wall-clock budget: a busy machine must not change a test's
/// result.
VerifySettings unhurried(VerifySettings settings) {
  settings.max_wall_seconds = std::numeric_limits<double>::infinity();
  return settings;
}

// --- the meshes made in code ---------------------------------------------------------------------

TEST(VerifyMeshes, GradedGridIsAValidConformingMeshOfTheWholeBox) {
  const TetMesh mesh = make_tet_mesh(grid_box_tets({-2.0, -0.5, 0.0, 0.25, 3.0}, {0.0, 1.0},
                                                   {0.0, 0.1, 0.3}));
  EXPECT_EQ(mesh.num_vertices(), 5 * 2 * 3);
  EXPECT_EQ(mesh.num_tets(), 6 * 4 * 1 * 2);
  double volume = 0.0;
  const Eigen::Matrix3Xd& x = mesh.rest_positions();
  for (Eigen::Index t = 0; t < mesh.num_tets(); ++t) {
    const auto tet = mesh.tets().col(t);
    volume += (x.col(tet(1)) - x.col(tet(0)))
                  .dot((x.col(tet(2)) - x.col(tet(0))).cross(x.col(tet(3)) - x.col(tet(0))))
              / 6.0;
  }
  EXPECT_NEAR(volume, 5.0 * 1.0 * 0.3, 1e-12);
}

TEST(VerifyMeshes, IcosphereIsClosedOnItsSphere) {
  const TriMesh sphere = icosphere(2, 0.5);
  EXPECT_EQ(sphere.num_triangles(), 20 * 16);
  EXPECT_EQ(sphere.num_vertices(), 162);  // V - E + F = 2
  EXPECT_NEAR(sphere.vertices.colwise().norm().minCoeff(), 0.5, 1e-15);
  EXPECT_NEAR(sphere.vertices.colwise().norm().maxCoeff(), 0.5, 1e-15);
}

// --- the cases -----------------------------------------------------------------------------------

TEST(VerifyPatch, CorotationalFemReproducesTheUniformStrain) {
  const CaseResult result = patch_case(kFem, unhurried(quick_verify_settings()));
  EXPECT_EQ(result.status, CaseStatus::kPass) << describe(result);
  EXPECT_LT(measure(result, "interior_error").value, verify_tolerance::kPatch);
}

TEST(VerifyRigidMotion, CorotationalFemStaysPutAndPlainLinearFemDoesNot) {
  const VerifySettings settings = unhurried(quick_verify_settings());
  const CaseResult corotational = rigid_motion_case(kFem, settings);
  EXPECT_EQ(corotational.status, CaseStatus::kPass) << describe(corotational);
  // Plain linear FEM is not rotation invariant: the rotated rest shape is strained to it.
  const CaseResult linear =
      rigid_motion_case({"corotational_fem", {{"formulation", "linear"}}}, settings);
  EXPECT_EQ(linear.status, CaseStatus::kFail) << describe(linear);
  EXPECT_GT(measure(linear, "max_displacement").value, 100 * verify_tolerance::kRigidDisplacement);
}

TEST(VerifyRigidMotion, AModelWithoutEnergyIsJudgedOnItsDisplacement) {
  const CaseResult result =
      rigid_motion_case({"shape_matching", {{"rotation", "svd"}}}, unhurried(quick_verify_settings()));
  EXPECT_FALSE(measure(result, "elastic_energy").judged());
  EXPECT_THAT(result.note, HasSubstr("no elastic energy"));
  // With exact rotations its goals are the moved shape itself (its default, warm-started
  // quaternion iterations start from the identity and lag a body that starts 90 degrees away).
  EXPECT_EQ(result.status, CaseStatus::kPass) << describe(result);
}

TEST(VerifyCantilever, CorotationalFemConvergesTowardEulerBernoulli) {
  VerifySettings settings = unhurried(quick_verify_settings());
  settings.beam_levels = {1, 2, 4};
  const CaseResult result = cantilever_case(kFem, settings);
  EXPECT_EQ(result.status, CaseStatus::kPass) << describe(result);
  EXPECT_LT(measure(result, "refinement_ratio").value, 1.0);
  ASSERT_EQ(result.details["levels"].size(), 3u);
}

TEST(VerifyCantilever, AWrongYoungModulusInTheComparisonFails) {
  VerifySettings settings = unhurried(quick_verify_settings());
  settings.beam_levels = {1, 2, 4};
  settings.analytic_young_modulus = 0.1 * settings.beam_material.young_modulus;
  const CaseResult result = cantilever_case(kFem, settings);
  EXPECT_EQ(result.status, CaseStatus::kFail) << describe(result);
  EXPECT_GT(measure(result, "finest_error").value, 0.8);  // 10x the deflection it should be
}

/// The force at each depth rises with it.
void expect_force_rises_with_depth(const CaseResult& result) {
  const nlohmann::json& depths = result.details["depths"];
  ASSERT_EQ(depths.size(), 3u);
  for (std::size_t i = 1; i < depths.size(); ++i) {
    EXPECT_GT(depths[i]["force_n"].get<double>(), depths[i - 1]["force_n"].get<double>());
  }
}

TEST(VerifyHertz, CorotationalFemWithItsDefaultsPressesAsHertzSays) {
  // The command's own block (a quarter, on frictionless symmetry planes, 16k tets): the force
  // within 15% of Hertz's at 0.1, 0.2 and 0.3 R (0.96, 1.00, 1.01 measured), constant over each
  // hold and never falling while the sphere goes down (within 2%), no tet inverted.
  const CaseResult result = hertz_case(kFem, unhurried(default_verify_settings()));
  for (const char* name :
       {"force_ratio", "ratio_at_0.1R", "ratio_at_0.2R", "hold_drift", "largest_drop",
        "inverted_tets"}) {
    const Measure& m = measure(result, name);
    RecordProperty(name, std::to_string(m.value));
    EXPECT_TRUE(m.passes()) << name << " = " << m.value << "; " << describe(result);
  }
  EXPECT_EQ(result.status, CaseStatus::kPass) << describe(result);
  expect_force_rises_with_depth(result);
}

TEST(VerifyHertz, CorotationalFemsDefaultSolverGivesTheExactSolvesContactForce) {
  // The same contact on the same mesh, solved exactly (CHOLMOD) at every pass of the active
  // set: the default CG's force within 1% at every depth.
  const VerifySettings settings = unhurried(quick_verify_settings());
  const CaseResult fast = hertz_case(kFem, settings);
  const CaseResult exact = hertz_case({"corotational_fem", {{"solver", "cholmod"}}}, settings);
  for (const char* name : {"ratio_at_0.1R", "ratio_at_0.2R", "force_ratio"}) {
    const double ratio = measure(fast, name).value / measure(exact, name).value;
    RecordProperty(std::string(name) + "_default_over_exact", std::to_string(ratio));
    EXPECT_NEAR(ratio, 1.0, 0.01) << name << ": " << describe(fast) << " / " << describe(exact);
  }
}

TEST(VerifyHertz, NeoHookeanPressesAsHertzSaysOnTheQuickBlock) {
  // The converged reference's Newton solves on the command's block take a minute; the quick
  // block (2k tets) takes seconds: the force within 15% at every depth (1.09, 1.12, 1.13
  // measured), no tet inverted. Its step-to-step jitter (a 4% fall on this coarse block, where
  // a rim vertex holds a larger share of the force) is the command's to report.
  const CaseResult result = hertz_case({"neo_hookean"}, unhurried(quick_verify_settings()));
  for (const char* name : {"force_ratio", "ratio_at_0.1R", "ratio_at_0.2R", "inverted_tets"}) {
    const Measure& m = measure(result, name);
    RecordProperty(name, std::to_string(m.value));
    EXPECT_TRUE(m.passes()) << name << " = " << m.value << "; " << describe(result);
  }
  expect_force_rises_with_depth(result);
}

TEST(VerifyFreeSpin, SymplecticEulerKeepsAngularMomentumAndBackwardEulerLosesIt) {
  VerifySettings settings = unhurried(quick_verify_settings());
  settings.spin.dt = 1.0 / 960.0;  // below the explicit integrator's stability limit
  const CaseResult symplectic = free_spin_case(
      {"mass_spring", {{"integrator", "symplectic_euler"}, {"damping", 0.0}}}, settings);
  EXPECT_EQ(symplectic.status, CaseStatus::kPass) << describe(symplectic);
  EXPECT_LT(measure(symplectic, "momentum_drift").value, 1e-10);
  // mass_spring's linearised backward Euler loses L at first order: tens of percent at 1/60 s.
  const CaseResult backward = free_spin_case({"mass_spring"}, unhurried(quick_verify_settings()));
  EXPECT_EQ(backward.status, CaseStatus::kFail) << describe(backward);
  EXPECT_GT(measure(backward, "momentum_drift").value, verify_tolerance::kSpinMomentum);
  EXPECT_TRUE(measure(backward, "shape_error").passes()) << describe(backward);
}

TEST(VerifySquashRelease, CorotationalFemRecovers) {
  const CaseResult result = squash_release_case(kFem, unhurried(quick_verify_settings()));
  EXPECT_EQ(result.status, CaseStatus::kPass) << describe(result);
  EXPECT_LT(measure(result, "residual").value, kRecoveredResidual);
}

// --- the command's run and reports ----------------------------------------------------------------

VerifyReport small_report() {
  VerifyOptions options;
  options.models = {"corotational_fem", "shape_matching"};
  options.cases = {"rigid_motion", "patch"};
  options.settings = unhurried(quick_verify_settings());
  return run_verify(options);
}

TEST(VerifyReport, JsonHasTheSchemaProvenanceAndEveryCaseWithItsTolerance) {
  const VerifyReport report = small_report();
  const nlohmann::json json = verify_json(report);
  EXPECT_EQ(json["schema_version"], kVerifySchemaVersion);
  EXPECT_TRUE(json["provenance"].contains("revision"));
  EXPECT_TRUE(json["settings"]["quick"].get<bool>());
  EXPECT_EQ(json["tolerances"]["patch"], verify_tolerance::kPatch);
  ASSERT_EQ(json["models"].size(), 2u);
  const nlohmann::json& fem = json["models"][0];
  EXPECT_EQ(fem["model"], "corotational_fem");
  ASSERT_EQ(fem["cases"].size(), 2u);
  const nlohmann::json& rigid = fem["cases"][0];
  EXPECT_EQ(rigid["name"], "rigid_motion");
  EXPECT_EQ(rigid["status"], "pass");
  EXPECT_GE(rigid["seconds"].get<double>(), 0.0);
  EXPECT_EQ(rigid["measures"][0]["name"], "max_displacement");
  EXPECT_EQ(rigid["measures"][0]["tolerance"], verify_tolerance::kRigidDisplacement);
  EXPECT_TRUE(rigid["measures"][0]["pass"].get<bool>());
  // shape_matching has no elastic energy: null in JSON, not judged.
  EXPECT_TRUE(json["models"][1]["cases"][0]["measures"][1]["value"].is_null());
  EXPECT_FALSE(json["models"][1]["cases"][0]["measures"][1]["judged"].get<bool>());
}

TEST(VerifyReport, MarkdownHasARowPerModelAndAColumnPerCase) {
  const std::string markdown = verify_markdown(small_report());
  EXPECT_THAT(markdown, HasSubstr("| model | rigid_motion | patch |"));
  EXPECT_THAT(markdown, ::testing::ContainsRegex("\\| corotational_fem \\| [0-9.e-]+ \\*\\*PASS\\*\\*"));
  EXPECT_THAT(markdown, HasSubstr("| shape_matching |"));
}

TEST(VerifyReport, WritesBothFiles) {
  const test::TempDir dir;
  write_verify(dir.path() / "out", small_report());
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "out" / "verify.md"));
  std::ifstream in(dir.path() / "out" / "verify.json");
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_EQ(json["schema_version"], kVerifySchemaVersion);
}

TEST(VerifyReport, AnUnknownModelOrCaseIsAnInputErrorBeforeAnythingRuns) {
  VerifyOptions options;
  options.models = {"corotational_fem", "no_such"};
  EXPECT_THROW(run_verify(options), InputError);
  options.models = {"corotational_fem"};
  options.cases = {"no_such"};
  EXPECT_THROW(run_verify(options), InputError);
}

}  // namespace
}  // namespace softbench::harness
