// SPDX-License-Identifier: MIT
#include "harness/stability/stability.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "harness/report/python_plot.h"
#include "harness/report/stability_report.h"
#include "harness/stability/torture_shapes.h"
#include "scenes/scene.h"
#include "scenes/scene_regions.h"
#include "tests/harness/plot_checks.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

namespace softbench::harness {
namespace {

using ::testing::HasSubstr;

// --- the tortured shapes -------------------------------------------------------------------------

// A 8 x 4 x 2 cm box: longest axis x, shortest z.
Eigen::Matrix3Xd box_rest() {
  return test::box_tets(4, 2, 1, 0.08, 0.04, 0.02).vertices;
}

TEST(TortureShapes, SquashFlattensTheShortestAxisOntoTheCentroidAndKeepsTheOthers) {
  const Eigen::Matrix3Xd rest = box_rest();
  const Eigen::Matrix3Xd squashed = squashed_to_plane(rest);
  EXPECT_DOUBLE_EQ(squashed.row(2).maxCoeff(), squashed.row(2).minCoeff());
  EXPECT_NEAR(squashed(2, 0), rest.row(2).mean(), 1e-15);
  EXPECT_EQ(squashed.topRows(2), rest.topRows(2));
}

TEST(TortureShapes, CollapseStaysInItsBallIsSeededAndKeepsVerticesDistinct) {
  const Eigen::Matrix3Xd rest = box_rest();
  const Eigen::Matrix<double, 3, 2> box = bounding_box(rest);
  const double radius = 1e-3 * (box.col(1) - box.col(0)).norm();
  const Eigen::Matrix3Xd collapsed = collapsed_to_point(rest, 1e-3, 9);
  const Eigen::Vector3d center = rest.rowwise().mean();
  EXPECT_LE((collapsed.colwise() - center).colwise().norm().maxCoeff(), radius);
  EXPECT_NE(collapsed.col(0), collapsed.col(1));
  EXPECT_EQ(collapsed, collapsed_to_point(rest, 1e-3, 9));
  EXPECT_NE(collapsed, collapsed_to_point(rest, 1e-3, 10));
}

TEST(TortureShapes, ScrambleFillsTheBoundingBoxAndInvertsAboutHalfTheTets) {
  const MeshData data = test::box_tets(4, 4, 4);
  const TetMesh mesh = make_tet_mesh(data);
  const Eigen::Matrix3Xd scrambled_positions = scrambled(mesh.rest_positions(), 9);
  const Eigen::Matrix<double, 3, 2> box = bounding_box(scrambled_positions);
  EXPECT_GE(box.minCoeff(), 0.0);
  EXPECT_LE(box.maxCoeff(), 1.0);
  int inverted = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::Vector4i tet = mesh.tets().col(t);
    inverted += signed_tet_volume(scrambled_positions.col(tet(0)), scrambled_positions.col(tet(1)),
                                  scrambled_positions.col(tet(2)), scrambled_positions.col(tet(3)))
                < 0.0;
  }
  // 384 tets, each inverted with probability 1/2: 5 sigma is +-49.
  EXPECT_NEAR(inverted, mesh.num_tets() / 2, 49);
}

TEST(TortureShapes, StretchTriplesTheLongestExtentAboutTheCentroid) {
  const Eigen::Matrix3Xd rest = box_rest();
  const Eigen::Matrix3Xd long_box = stretched(rest, 3.0);
  EXPECT_NEAR(long_box.row(0).maxCoeff() - long_box.row(0).minCoeff(), 0.24, 1e-12);
  EXPECT_NEAR(long_box.row(0).mean(), rest.row(0).mean(), 1e-12);
  EXPECT_EQ(long_box.bottomRows(2), rest.bottomRows(2));
}

TEST(TortureShapes, FlattenOneTetMakesOneSliverOfTheRequestedQualityAwayFromKeptVertices) {
  const TetMesh mesh = make_tet_mesh(test::box_tets(3, 3, 3));
  std::vector<int> keep;
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    if (mesh.rest_positions()(0, i) < 1e-9) {
      keep.push_back(i);
    }
  }
  const std::optional<Sliver> sliver = flatten_one_tet(mesh, keep, 1e-3);
  ASSERT_TRUE(sliver.has_value());
  EXPECT_NEAR(sliver->quality, 1e-3, 1e-6);
  EXPECT_EQ(std::find(keep.begin(), keep.end(), sliver->vertex), keep.end());
  const Eigen::Matrix3Xd& x = sliver->mesh.rest_positions();
  EXPECT_GT(sliver->moved, 0.0);
  EXPECT_NEAR((x - mesh.rest_positions()).colwise().norm().sum(), sliver->moved, 1e-15);
  // Only the sliver is near-degenerate; every tet keeps its orientation.
  EXPECT_GT(sliver->neighbour_quality, 0.01);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::Vector4i tet = mesh.tets().col(t);
    EXPECT_EQ(sliver->mesh.tets().col(t), tet);
    EXPECT_GT(signed_tet_volume(x.col(tet(0)), x.col(tet(1)), x.col(tet(2)), x.col(tet(3))), 0.0);
  }
  EXPECT_NEAR(tet_quality(x, sliver->mesh.tets()).min_radius_ratio, 1e-3, 1e-6);
}

// --- the map scan --------------------------------------------------------------------------------

RunVerdict verdict_of(RunStatus status) {
  RunVerdict verdict;
  verdict.status = status;
  return verdict;
}

TEST(ScanTimeSteps, StopsAtTheFirstStableStepFromTheLargest) {
  const std::vector<double> steps = {1.0 / 30, 1.0 / 60, 1.0 / 120, 1.0 / 240};
  std::vector<double> tried;
  const MapRow row = scan_time_steps(5.0, steps, [&](double dt) {
    tried.push_back(dt);
    return verdict_of(dt > 0.01 ? RunStatus::kUnstable : RunStatus::kStable);
  });
  EXPECT_EQ(row.value, 5.0);
  EXPECT_EQ(tried, (std::vector<double>{1.0 / 30, 1.0 / 60, 1.0 / 120}));
  ASSERT_TRUE(row.max_stable_dt.has_value());
  EXPECT_EQ(*row.max_stable_dt, 1.0 / 120);
  ASSERT_EQ(row.cells.size(), 4u);
  EXPECT_TRUE(row.cells[0].is(RunStatus::kUnstable));
  EXPECT_TRUE(row.cells[1].is(RunStatus::kUnstable));
  EXPECT_TRUE(row.cells[2].is(RunStatus::kStable));
  EXPECT_FALSE(row.cells[3].verdict.has_value());  // not run
  EXPECT_EQ(row.cells[3].dt, 1.0 / 240);
}

TEST(ScanTimeSteps, UnstableEverywhereHasNoStableStepAndATimeoutEndsTheScan) {
  const std::vector<double> steps = {0.1, 0.05, 0.025};
  const MapRow never =
      scan_time_steps(1.0, steps, [](double) { return verdict_of(RunStatus::kUnstable); });
  EXPECT_FALSE(never.max_stable_dt.has_value());
  for (const MapCell& cell : never.cells) {
    EXPECT_TRUE(cell.is(RunStatus::kUnstable));
  }
  int runs = 0;
  const MapRow slow = scan_time_steps(1.0, steps, [&](double dt) {
    ++runs;
    return verdict_of(dt > 0.06 ? RunStatus::kUnstable : RunStatus::kTimedOut);
  });
  EXPECT_EQ(runs, 2);
  EXPECT_FALSE(slow.max_stable_dt.has_value());
  EXPECT_TRUE(slow.cells[1].is(RunStatus::kTimedOut));
  EXPECT_FALSE(slow.cells[2].verdict.has_value());
}

TEST(StiffnessAxis, MapsEachModelAlongWhatSetsItsStiffness) {
  const std::vector<double> moduli = {1e5, 1e3};
  const std::vector<double> unitless = {1.0, 0.1};
  const StiffnessAxis fem = stiffness_axis("corotational_fem", moduli, unitless);
  EXPECT_TRUE(fem.material);
  EXPECT_EQ(fem.values, (std::vector<double>{1e3, 1e5}));  // increasing
  const StiffnessAxis springs = stiffness_axis("mass_spring", moduli, unitless);
  EXPECT_TRUE(springs.material);
  EXPECT_EQ(springs.fixed_params["stiffness_from"], "young_modulus");
  const StiffnessAxis matching = stiffness_axis("shape_matching", moduli, unitless);
  EXPECT_FALSE(matching.material);
  EXPECT_EQ(matching.parameter, "alpha");
  EXPECT_EQ(matching.values, (std::vector<double>{0.1, 1.0}));
  EXPECT_EQ(stiffness_axis("bullet_softbody", moduli, unitless).parameter, "stiffness");
  // A model whose registry entry declares no axis (the reference, a new model) is mapped along E.
  EXPECT_EQ(stiffness_axis("neo_hookean", moduli, unitless).parameter, "young_modulus");
}

// --- real runs on a small mesh made in code ------------------------------------------------------

// An 8 x 4 x 4 cm bar (45 vertices, 96 tets) clamped at x = 0, 30 kPa, sagging under gravity
// for 0.5 s, then let go (the scene runs of nu = 0.49 and the sliver extend it by the recovery
// window). Every model with its default parameters.
class StabilityRuns : public ::testing::Test {
 protected:
  void SetUp() override {
    data_ = test::box_tets(4, 2, 2, 0.08, 0.04, 0.04);
    write_msh(dir_.path() / "bar.msh", data_);
    const auto path = dir_.write("bar.json", R"({
      "name": "bar",
      "mesh": "bar.msh",
      "material": {"young_modulus": 30000, "poisson_ratio": 0.3, "density": 1000},
      "gravity": {"acceleration": [0, 0, -9.81], "off_at": 0.5},
      "time": {"dt": 0.016666666666666666, "duration": 1.0},
      "fixed": {"box": {"min": [-0.001, -1, -1], "max": [0.001, 1, 1]}}
    })");
    scene_ = scenes::load_scene(path);
  }

  // Shape matching's pull is per step and, on a bar held at one end, takes 10-16 s to bring
  // a scramble or a collapse back within 1%: a 20 s window (1200 steps of 45 vertices).
  StabilitySettings settings() const {
    StabilitySettings settings = quick_stability_settings();
    settings.recovery_window = 20.0;
    return settings;
  }

  test::TempDir dir_;
  MeshData data_;
  scenes::Scene scene_;
};

TEST_F(StabilityRuns, CorotationalFemAndShapeMatchingSurviveAndRecoverFromEveryTorture) {
  const SceneMesh mesh = read_scene_mesh(scene_);
  StabilitySettings only_torture = settings();
  only_torture.young_moduli.clear();
  only_torture.unitless.clear();
  for (const std::string model : {"corotational_fem", "shape_matching"}) {
    const ModelStability result = model_stability(scene_, mesh, model, only_torture);
    ASSERT_EQ(result.torture.size(), 6u);
    for (const TortureResult& torture : result.torture) {
      const std::string what = model + " " + torture_name(torture.which) + ": " + torture.note;
      ASSERT_TRUE(torture.run) << what;
      EXPECT_TRUE(torture.verdict.stable()) << what << ": " << torture.verdict.failure;
      EXPECT_FALSE(torture.verdict.nan) << what;
      // Recovered: within 1% of the bbox diagonal of the rest (reference) shape at the end.
      EXPECT_TRUE(torture.recovered) << what << ": residual " << torture.verdict.residual;
      EXPECT_LT(torture.verdict.residual, 0.01) << what;
      // It ran to the end of the window, or until it had come to rest.
      EXPECT_TRUE(torture.verdict.steps_run == torture.verdict.steps_planned
                  || torture.verdict.settled_after.has_value())
          << what;
      // At rest under its load before the release does not count as settled.
      EXPECT_GT(torture.verdict.settled_after.value_or(1.0), 0.0) << what;
    }
  }
}

TEST_F(StabilityRuns, TheMapFindsTheLargestStableStepOfAnExplicitModel) {
  const SceneMesh mesh = read_scene_mesh(scene_);
  // Symplectic-Euler springs at 1 MPa on ~2 cm edges: far beyond its CFL limit at 1/30 s.
  scene_.model_parameters["mass_spring"] = {{"integrator", "symplectic_euler"}, {"damping", 0.0}};
  StabilitySettings map_only = settings();
  map_only.cases.clear();
  map_only.young_moduli = {1e2, 1e6};
  map_only.time_steps = {1.0 / 30, 1.0 / 240, 1.0 / 1920, 1.0 / 15360};
  map_only.map_duration = 0.1;
  const ModelStability springs = model_stability(scene_, mesh, "mass_spring", map_only);
  ASSERT_EQ(springs.map.size(), 2u);
  EXPECT_EQ(springs.axis.parameter, "young_modulus");
  const MapRow& soft = springs.map[0];
  const MapRow& stiff = springs.map[1];
  EXPECT_EQ(soft.value, 1e2);
  ASSERT_TRUE(soft.max_stable_dt && stiff.max_stable_dt);
  // The stiffer material needs a smaller step, and the scan stopped at its first stable one.
  EXPECT_LT(*stiff.max_stable_dt, *soft.max_stable_dt);
  ASSERT_TRUE(stiff.cells[0].is(RunStatus::kUnstable));
  EXPECT_THAT(stiff.cells[0].verdict->failure,
              ::testing::AnyOf(HasSubstr("NaN"), HasSubstr("over the limit")));
  for (const MapRow& row : springs.map) {
    bool seen_stable = false;
    for (const MapCell& cell : row.cells) {
      EXPECT_EQ(!cell.verdict.has_value(), seen_stable);
      seen_stable = seen_stable || cell.is(RunStatus::kStable);
    }
  }

  // Shape matching at any alpha: stable at the largest step.
  const ModelStability matching = model_stability(scene_, mesh, "shape_matching", map_only);
  EXPECT_EQ(matching.axis.parameter, "alpha");
  for (const MapRow& row : matching.map) {
    EXPECT_TRUE(row.cells[0].is(RunStatus::kStable)) << "alpha " << row.value;
  }
}

TEST_F(StabilityRuns, RefusesAFreeBodyNamingTheFixedRegion) {
  const SceneMesh mesh = read_scene_mesh(scene_);
  scene_.fixed = {};
  try {
    model_stability(scene_, mesh, "corotational_fem", settings());
    ADD_FAILURE() << "no InputError for a scene without a fixed region";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              scene_.source.string()
                  + ": /fixed: absent (a free body); stability needs a fixed region: its map "
                    "hangs the body from it under gravity, and its torture cases let the body "
                    "recover with it held");
  }
}

// --- claims and reports --------------------------------------------------------------------------

TortureResult torture_of(TortureCase which, RunStatus status, double residual) {
  TortureResult torture;
  torture.which = which;
  torture.run = true;
  torture.verdict = verdict_of(status);
  torture.verdict.residual = residual;
  torture.recovered = torture.verdict.recovered();
  return torture;
}

StabilityReport sample_report() {
  StabilityReport report;
  report.scene = "sample";
  report.scene_file = "sample.json";
  report.scene_dt = 1.0 / 60;
  report.settings = quick_stability_settings();
  ModelStability matching;
  matching.model = "shape_matching";
  matching.axis = stiffness_axis("shape_matching", {}, {0.1, 1.0});
  matching.map = {scan_time_steps(0.1, report.settings.time_steps,
                                  [](double) { return verdict_of(RunStatus::kStable); }),
                  scan_time_steps(1.0, report.settings.time_steps, [](double dt) {
                    return verdict_of(dt > 0.02 ? RunStatus::kUnstable : RunStatus::kStable);
                  })};
  matching.torture = {torture_of(TortureCase::kSquash, RunStatus::kStable, 0.001)};
  ModelStability springs;
  springs.model = "mass_spring";
  springs.axis = stiffness_axis("mass_spring", {1e3}, {});
  springs.map = {scan_time_steps(1e3, report.settings.time_steps,
                                 [](double) { return verdict_of(RunStatus::kStable); })};
  springs.torture = {torture_of(TortureCase::kSquash, RunStatus::kStable, 0.2),
                     torture_of(TortureCase::kStretch, RunStatus::kStable, 0.001),
                     torture_of(TortureCase::kIncompressible, RunStatus::kUnstable, NAN)};
  report.models = {matching, springs};
  report.claims = check_claims(report.models, report.settings);
  return report;
}

TEST(StabilityClaims, AreJudgedFromTheMapAndTheLargeDeformationTortures) {
  const StabilityReport report = sample_report();
  ASSERT_EQ(report.claims.size(), 2u);
  // One unstable map cell (alpha 1 at 1/30 s) refutes unconditional stability.
  EXPECT_EQ(report.claims[0].verdict, Verdict::kFail);
  EXPECT_THAT(report.claims[0].evidence, HasSubstr("alpha 1 at dt 1/30 s"));
  EXPECT_THAT(report.claims[0].evidence, ::testing::Not(HasSubstr("never a NaN")));
  // Not recovering from the squash supports the mass-spring claim; the nu = 0.49 run is not a
  // large deformation and does not count.
  EXPECT_EQ(report.claims[1].verdict, Verdict::kObserved);
  EXPECT_THAT(report.claims[1].evidence, HasSubstr("squash_to_plane (residual 20%"));
  EXPECT_THAT(report.claims[1].evidence, HasSubstr("recovers from: stretch_3x"));
  EXPECT_THAT(report.claims[1].evidence, ::testing::Not(HasSubstr("poisson")));

  const std::vector<Claim> none = check_claims({}, report.settings);
  EXPECT_EQ(none[0].verdict, Verdict::kNotRun);
  EXPECT_EQ(none[1].verdict, Verdict::kNotRun);
}

TEST(StabilityReport, MarkdownAndJsonCarryTheTablesAndThePlotScriptDrawsAHeatMapPerModel) {
  const StabilityReport report = sample_report();
  const std::string markdown = stability_markdown(report);
  EXPECT_THAT(markdown, HasSubstr("**FAIL** Shape matching is unconditionally stable"));
  EXPECT_THAT(markdown, HasSubstr("**OBSERVED** Mass-spring may fail at large deformation"));
  EXPECT_THAT(markdown, HasSubstr("| shape_matching | alpha"));
  EXPECT_THAT(markdown, HasSubstr("| 1/30 | 1/60 |"));  // alpha 0.1 and 1
  EXPECT_THAT(markdown,
              HasSubstr("| mass_spring | squash_to_plane | yes | **no** | no | 0 / 0 | 20%"));
  EXPECT_THAT(markdown, HasSubstr("| mass_spring | poisson_0.49 | **NO**"));

  const nlohmann::json json = stability_json(report);
  ASSERT_EQ(json["models"].size(), 2u);
  const nlohmann::json& row = json["models"][0]["map"][1];
  EXPECT_EQ(row["max_stable_dt"], 1.0 / 60);
  EXPECT_EQ(row["cells"][0]["status"], "unstable");
  EXPECT_EQ(row["cells"][2]["status"], "not_run");
  EXPECT_EQ(json["models"][1]["torture"][0]["recovered"], false);
  EXPECT_EQ(json["claims"][1]["verdict"], "observed");
  EXPECT_TRUE(json["provenance"].contains("revision"));

  const test::TempDir dir;
  write_stability(dir.path(), report);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "stability.md"));
  if (!find_plot_script("plot_stability.py", "SOFTBENCH_STABILITY_SCRIPT") || !plotting_python()) {
    GTEST_SKIP() << "no python3 with matplotlib: heat maps not checked";
  }
  const PlotOutcome plots = run_plot_script("plot_stability.py", "SOFTBENCH_STABILITY_SCRIPT",
                                            dir.path() / "stability.json", dir.path());
  ASSERT_TRUE(plots.plotted) << plots.message;
  test::expect_png_files(plots, dir.path(),
                         {"stability_shape_matching.png", "stability_mass_spring.png"});
}

}  // namespace
}  // namespace softbench::harness
