// SPDX-License-Identifier: MIT
#include "harness/sweep/sweep.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "harness/run/scene_mesh.h"
#include "harness/sweep/recommend.h"
#include "models/json_file.h"
#include "models/model_registry.h"
#include "scenes/scene.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace softbench::harness {
namespace {

using ::testing::HasSubstr;

TEST(SweepAxis, ParsesFractionsIntegersAndStrings) {
  const SweepAxis dt = parse_sweep_axis("model.dt=1/30,1/60,0.005");
  EXPECT_EQ(dt.model, "model");
  EXPECT_EQ(dt.key, "dt");
  ASSERT_EQ(dt.values.size(), 3u);
  EXPECT_DOUBLE_EQ(dt.values[0].get<double>(), 1.0 / 30.0);
  EXPECT_DOUBLE_EQ(dt.values[2].get<double>(), 0.005);
  const SweepAxis clusters = parse_sweep_axis("shape_matching.clusters=1,10,50");
  EXPECT_TRUE(clusters.values[1].is_number_integer());  // integer parameters reject 10.0
  EXPECT_EQ(parse_sweep_axis("shape_matching.type=linear,quadratic").values[1], "quadratic");
}

TEST(SweepAxis, RejectsMalformedArguments) {
  for (const char* bad : {"dt=1/30", "model.dt", ".dt=1", "model.=1", "model.dt=", "model.dt=1,,2",
                          "model.dt=0", "model.dt=fast"}) {
    EXPECT_THROW(parse_sweep_axis(bad), InputError) << bad;
  }
}

// A 10 x 2 x 2 cm bar clamped at one end, sagging under gravity for half a second.
class SweepTest : public ::testing::Test {
 protected:
  SweepTest() { write_msh(dir_.path() / "bar.msh", test::box_tets(5, 1, 1, 0.1, 0.02, 0.02)); }

  scenes::Scene scene(const std::string& models = R"({"corotational_fem": {"rayleigh_mass": 2.0},
                 "mass_spring": {"stiffness_from": "young_modulus", "damping": 0.5}})",
                      const std::string& file = "bar.json") const {
    return scenes::load_scene(dir_.write(file, R"({
      "name": "bar",
      "mesh": "bar.msh",
      "material": {"young_modulus": 50000, "poisson_ratio": 0.3, "density": 1000},
      "gravity": [0, 0, -9.81],
      "time": {"dt": 0.02, "duration": 0.4},
      "fixed": {"box": {"min": [-0.001, -1, -1], "max": [0.001, 1, 1]}},
      "requirements": {"steps_per_second": 10, "accuracy": 0.05},
      "models": )" + models + "}"));
  }

  // corotational_fem at dt 1/50 and 1/100 against the same model at two substeps of the
  // scene's dt (0.01 s), compared at four times, into `folder`.
  SweepOptions two_dt_sweep(const std::string& folder) const {
    SweepOptions options;
    options.axes = {parse_sweep_axis("model.dt=1/50,1/100")};
    options.models = {"corotational_fem"};
    options.reference.model = "corotational_fem";
    options.reference.substeps = 2;
    options.reference.times = 4;
    options.out_dir = dir_.path() / folder;
    return options;
  }

  // Shard `shard` of two of `options`, into its own folder.
  SweepOptions half(const SweepOptions& options, int shard) const {
    SweepOptions part = options;
    part.shard = shard;
    part.shards = 2;
    part.out_dir = dir_.path() / ("shard" + std::to_string(shard));
    return part;
  }

  test::TempDir dir_;
};

TEST_F(SweepTest, GridIsTheProductOfTheAxesThatApplyToEachModel) {
  const std::vector<std::string> models = {"corotational_fem", "mass_spring"};
  const std::vector<SweepPoint> points = sweep_grid(
      scene(), "mesh",
      {parse_sweep_axis("model.dt=1/50,1/100"), parse_sweep_axis("mass_spring.damping=0.1,0.5,1")},
      models, "neo_hookean");
  int fem = 0;
  int springs = 0;
  std::set<std::string> ids;
  for (const SweepPoint& point : points) {
    (point.model == "corotational_fem" ? fem : springs) += 1;
    ids.insert(point.id);
    EXPECT_EQ(point.dt, point.settings["dt"].get<double>());
  }
  EXPECT_EQ(fem, 2);
  EXPECT_EQ(springs, 6);
  EXPECT_EQ(ids.size(), points.size());
  // The same sweep names its runs the same way (that is what makes it resumable).
  EXPECT_EQ(
      sweep_grid(scene(), "mesh", {parse_sweep_axis("model.dt=1/50,1/100")}, models, "")[1].id,
      points[1].id);
  // Another mesh (or build) names them differently: shards of two meshes never merge.
  EXPECT_NE(
      sweep_grid(scene(), "other", {parse_sweep_axis("model.dt=1/50,1/100")}, models, "")[1].id,
      points[1].id);
}

TEST_F(SweepTest, GridRunsEveryDefaultModelAModelWithoutABlockWithItsDefaults) {
  std::set<std::string> swept;
  for (const SweepPoint& point : sweep_grid(scene(), "mesh", {}, {}, "neo_hookean")) {
    swept.insert(point.model);
    EXPECT_TRUE(point.settings.empty());
  }
  std::set<std::string> expected;
  for (const std::string& name : builtin_models().default_names()) {
    expected.insert(name);
  }
  EXPECT_EQ(swept, expected);  // shape_matching has no block in the scene and is swept too
  EXPECT_TRUE(swept.count("shape_matching"));
}

TEST_F(SweepTest, GridLeavesOutTheReferenceAndRejectsAnAxisForAnotherModel) {
  for (const SweepPoint& point : sweep_grid(scene(), "mesh", {}, {}, "mass_spring")) {
    EXPECT_NE(point.model, "mass_spring");
  }
  try {
    sweep_grid(scene(), "mesh", {parse_sweep_axis("shape_matching.clusters=1,2")},
               {"corotational_fem", "mass_spring"}, "");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("shape_matching is not among the swept models"));
  }
}

// A swept dt meets the scene loader's step limit: 0.4 s at 1e-300 s would not fit in memory.
TEST_F(SweepTest, GridRejectsADtOverTheStepLimit) {
  try {
    sweep_grid(scene(), "mesh", {parse_sweep_axis("model.dt=1e-300")}, {"mass_spring"}, "");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "--param model.dt: dt = 1e-300 s is 4e+299 steps of the scene's 0.4 s, over the "
                 "limit of 10000000");
  }
}

// merge writes each record it reads as runs/<id>.json: an id from a file must not be a path.
TEST_F(SweepTest, RejectsARecordWhoseIdIsAPath) {
  nlohmann::json json = {{"id", "../../x"}};
  try {
    sweep_record_from_json(json, "r.json");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "r.json: /id: expected a run id (letters, digits, '_' or '-'), got \"../../x\"");
  }
}

TEST(SweepAccuracy, IsZeroOnTheReferenceAndScalesWithTheOffset) {
  const Eigen::Matrix3Xd rest = Eigen::Matrix3Xd::Zero(3, 4);
  ReferenceRun reference;
  reference.times = {0.5, 1.0};
  reference.positions = {Eigen::Matrix3Xd::Constant(3, 4, 0.1),
                         Eigen::Matrix3Xd::Constant(3, 4, 0.2)};
  reference.volumes = {1.0, 1.0};
  reference.peak_tool_force = 2.0;
  ModelRun run;
  run.contact.peak_tool_force = 3.0;
  for (std::size_t i = 0; i < 2; ++i) {
    run.snapshots.push_back({reference.times[i], reference.positions[i], 1.0});
  }
  Accuracy same = accuracy_against(run.snapshots, run.contact.peak_tool_force, reference, rest);
  EXPECT_EQ(same.rms_error, 0.0);
  EXPECT_EQ(same.volume_error, 0.0);
  EXPECT_DOUBLE_EQ(*same.peak_force_error, 0.5);
  // Off by 10% of the reference's displacement at both times.
  run.snapshots[0].positions *= 1.1;
  run.snapshots[1].positions *= 1.1;
  run.snapshots[1].volume = 1.2;
  const Accuracy off =
      accuracy_against(run.snapshots, run.contact.peak_tool_force, reference, rest);
  EXPECT_NEAR(off.rms_error, 0.1, 1e-12);
  EXPECT_NEAR(off.max_error, 0.1, 1e-12);
  EXPECT_NEAR(off.volume_error, 0.2, 1e-12);
  run.snapshots.pop_back();  // blew up before the last time
  EXPECT_TRUE(std::isinf(
      accuracy_against(run.snapshots, run.contact.peak_tool_force, reference, rest).rms_error));
}

SweepRecord record(const std::string& model, double speed, double error, bool stable = true) {
  SweepRecord r;
  r.point.model = model;
  r.point.id = model + std::to_string(speed);
  r.point.settings = nlohmann::json::object();
  r.steps_per_second = speed;
  r.accuracy.rms_error = error;
  r.accuracy.volume_error = error;
  r.stable = stable;
  return r;
}

TEST(SweepTable, ParetoFrontKeepsOnlyUnbeatenRunsPerModel) {
  const std::vector<SweepRecord> records = {record("a", 100, 0.1), record("a", 50, 0.2),
                                            record("a", 10, 0.01), record("b", 1000, 0.5),
                                            record("b", 2000, 0.4, false)};
  std::set<std::string> front;
  for (const SweepRecord& r : pareto_front(records)) {
    front.insert(r.point.id);
  }
  EXPECT_EQ(front, (std::set<std::string>{"a100.000000", "a10.000000", "b1000.000000"}));
  EXPECT_EQ(fastest_within(records, 0.05)->point.id, "a10.000000");
  EXPECT_EQ(fastest_within(records, 0.6)->point.id, "b1000.000000");  // the unstable one is out
  EXPECT_FALSE(fastest_within(records, 0.001).has_value());
}

TEST(SweepTable, CsvRowsLineUpWithTheHeader) {
  test::TempDir dir;
  SweepRecord r = record("a", 120, 0.25);
  r.point.dt = 0.5;
  r.point.settings = {{"cg_tolerance", 0.01}, {"solver", "cg"}};
  write_sweep_table(dir.path(), "scene", {r}, {});
  std::ifstream in(dir.path() / "sweep.csv");
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  // The settings cell is the only one with commas: split it out, then compare cell by cell.
  const auto quote = row.find('"');
  const auto unquote = row.find('"', quote + 1);
  ASSERT_NE(unquote, std::string::npos) << row;
  EXPECT_EQ(row.substr(quote, unquote - quote + 1), "\"{'cg_tolerance':0.01,'solver':'cg'}\"");
  row.replace(quote, unquote - quote + 1, "SETTINGS");
  auto cells = [](const std::string& line) {
    std::vector<std::string> out;
    std::stringstream stream(line);
    for (std::string cell; std::getline(stream, cell, ',');) {
      out.push_back(cell);
    }
    return out;
  };
  const std::vector<std::string> names = cells(header);
  const std::vector<std::string> values = cells(row);
  ASSERT_EQ(names.size(), values.size()) << header << "\n" << row;
  std::map<std::string, std::string> by_name;
  for (std::size_t i = 0; i < names.size(); ++i) {
    by_name[names[i]] = values[i];
  }
  EXPECT_EQ(by_name["id"], r.point.id);
  EXPECT_EQ(by_name["model"], "a");
  EXPECT_EQ(by_name["settings"], "SETTINGS");
  EXPECT_EQ(by_name["stable"], "true");
  EXPECT_EQ(std::stod(by_name["steps_per_second"]), 120.0);
  EXPECT_EQ(std::stod(by_name["realtime_factor"]), 60.0);  // steps/s x dt
  EXPECT_EQ(std::stod(by_name["rms_error"]), 0.25);
  EXPECT_EQ(std::stod(by_name["volume_error"]), 0.25);
  EXPECT_EQ(by_name["peak_force_error"], "null");
}

TEST(Recommend, PicksTheFastestRunMeetingEveryRequirementAndSaysWhatOthersMiss) {
  scenes::Requirements requirements;
  requirements.steps_per_second = 60;
  requirements.accuracy = 0.05;
  const std::vector<SweepRecord> records = {record("fem", 300, 0.02), record("fem", 900, 0.08),
                                            record("springs", 2000, 0.3),
                                            record("slow", 20, 0.001)};
  const Recommendation result = recommend(requirements, records);
  ASSERT_TRUE(result.choice.has_value());
  EXPECT_EQ(result.choice->point.id, "fem300.000000");
  EXPECT_THAT(result.explanation, HasSubstr("position error 30% > 5%"));
  EXPECT_THAT(result.explanation, HasSubstr("20 steps/s < 60"));
  requirements.outputs = {"contact_force"};
  EXPECT_THAT(shortfall(records[0], requirements), HasSubstr("no contact force"));
  requirements.steps_per_second = 1e6;
  EXPECT_FALSE(recommend(requirements, records).choice.has_value());
}

TEST_F(SweepTest, RunsResumesShardsAndMeasuresErrorAgainstTheReference) {
  // The reference is the same model at dt / 2 = 0.01 s: the dt = 1/100 run is that very
  // computation (error 0), the dt = 1/50 one is not.
  const SweepOptions options = two_dt_sweep("full");
  const std::vector<SweepRecord> records = run_sweep(scene(), options).records;
  ASSERT_EQ(records.size(), 2u);
  const SweepRecord& coarse = records[0].point.dt > records[1].point.dt ? records[0] : records[1];
  const SweepRecord& fine = records[0].point.dt > records[1].point.dt ? records[1] : records[0];
  EXPECT_LT(fine.accuracy.rms_error, 1e-9);
  EXPECT_GT(coarse.accuracy.rms_error, 1e-4);
  EXPECT_GT(coarse.steps_per_second, 0.0);
  // Simulated seconds per wall second: steps/s x dt.
  EXPECT_DOUBLE_EQ(to_json(coarse)["realtime_factor"].get<double>(),
                   coarse.steps_per_second * coarse.point.dt);

  // Resuming runs nothing: a record file left alone keeps its (edited) contents.
  const auto file = options.out_dir / "runs" / (coarse.point.id + ".json");
  nlohmann::json edited = to_json(coarse);
  edited["steps_per_second"] = 1.0;
  std::ofstream(file) << edited.dump();
  EXPECT_EQ(
      run_sweep(scene(), options).records[records[0].point.id == coarse.point.id ? 0 : 1].steps_per_second,
      1.0);

  // Two shards run disjoint halves; merged they are the whole sweep.
  std::vector<std::filesystem::path> shards;
  for (int shard = 0; shard < 2; ++shard) {
    const SweepOptions part = half(options, shard);
    EXPECT_EQ(run_sweep(scene(), part).records.size(), 1u);
    shards.push_back(part.out_dir);
  }
  const std::vector<SweepRecord> merged = read_sweep_runs(shards);
  ASSERT_EQ(merged.size(), 2u);
  EXPECT_NE(merged[0].point.id, merged[1].point.id);
}

// A sweep ranks models only against a reference that converged: the reference at twice its
// substeps moves the same, within the scene's accuracy. A damped bar sagging to rest does; an
// undamped one swinging under gravity does not (implicit Euler's numerical damping and phase
// differ at the two time steps), and its ranking is refused, in sweep.json and by recommend,
// unless the reference is trusted.
TEST_F(SweepTest, RanksOnlyAgainstAReferenceThatConverged) {
  const auto bar = [&](double damping) {
    const std::string name = "bar_" + std::to_string(damping);
    return scene(R"({"corotational_fem": {"rayleigh_mass": )" + std::to_string(damping) + "}}",
                 name + ".json");
  };
  const ReferenceSettings settings = two_dt_sweep("").reference;
  const auto check = [&](const scenes::Scene& scene) {
    const SceneMesh mesh = read_scene_mesh(scene);
    const std::filesystem::path cache = dir_.path() / ("cache_" + scene.source.stem().string());
    return reference_convergence(scene, mesh, settings, cache,
                                 reference_run(scene, mesh, settings, cache));
  };
  // Measured: 0.9% damped (60 /s), 14% undamped, against the scene's 5%.
  const ReferenceConvergence damped = check(bar(60.0));
  EXPECT_TRUE(damped.checked);
  EXPECT_EQ(damped.finer_substeps, 4);
  EXPECT_DOUBLE_EQ(damped.budget, 0.05);
  EXPECT_TRUE(damped.budget_from_scene);
  EXPECT_LT(damped.difference, 0.02);
  EXPECT_EQ(ranking_refusal(damped), "");
  const ReferenceConvergence swinging = check(bar(0.0));
  EXPECT_GT(swinging.difference, 0.1);
  EXPECT_THAT(ranking_refusal(swinging), HasSubstr("the reference has not converged: at 2 and 4 "
                                                   "substeps it differs by"));
  EXPECT_THAT(ranking_refusal(swinging), HasSubstr("more than the 5% the scene requires"));

  // The sweep on the swinging bar runs its models but ranks none of them; trusted, it ranks.
  SweepOptions options = two_dt_sweep("swinging");
  const scenes::Scene scene = bar(0.0);
  const auto [records, convergence] = run_sweep(scene, options);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_DOUBLE_EQ(convergence.difference, swinging.difference);
  EXPECT_DOUBLE_EQ(read_reference_convergence({options.out_dir}).difference,
                   swinging.difference);
  write_sweep_table(options.out_dir, "bar", records, convergence);
  const nlohmann::json table = read_json_file((options.out_dir / "sweep.json").string());
  EXPECT_THAT(table["ranking_refused"].get<std::string>(), HasSubstr("has not converged"));
  EXPECT_TRUE(table["pareto"].empty());
  EXPECT_TRUE(table["fastest_within"]["20%"].is_null());
  options.trust_reference = true;
  options.out_dir = dir_.path() / "trusted";
  const SweepResult trusted = run_sweep(scene, options);
  EXPECT_FALSE(trusted.convergence.checked);
  EXPECT_FALSE(read_reference_convergence({options.out_dir}).checked);
  write_sweep_table(options.out_dir, "bar", trusted.records, trusted.convergence);
  EXPECT_FALSE(read_json_file((options.out_dir / "sweep.json").string())["pareto"].empty());
}

// On a cluster the reference is computed once, into a shared folder, before the shards start:
// the shards read it (and its check) and compute neither again.
TEST_F(SweepTest, ShardsShareOneReferenceComputedBeforeThem) {
  SweepOptions options = two_dt_sweep("reference_step");
  options.reference_dir = dir_.path() / "shared_reference";
  options.reference_only = true;
  EXPECT_TRUE(run_sweep(scene(), options).records.empty());
  const auto written_files = [&] {
    std::map<std::filesystem::path, std::filesystem::file_time_type> written;
    for (const auto& entry : std::filesystem::directory_iterator(options.reference_dir)) {
      written[entry.path()] = entry.last_write_time();
    }
    return written;
  };
  // The reference and the finer run that checked it.
  const auto written = written_files();
  EXPECT_EQ(written.size(), 2u);
  options.reference_only = false;
  for (int shard = 0; shard < 2; ++shard) {
    const SweepOptions part = half(options, shard);
    EXPECT_EQ(run_sweep(scene(), part).records.size(), 1u);
    EXPECT_FALSE(std::filesystem::exists(part.out_dir / "reference"));
    EXPECT_TRUE(read_reference_convergence({part.out_dir}).checked);
  }
  EXPECT_EQ(written_files(), written);
}
}  // namespace
}  // namespace softbench::harness
