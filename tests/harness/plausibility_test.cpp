// SPDX-License-Identifier: MIT
// The plausibility checks on runs made in code: each warning fires on the run built to cross its
// threshold, and none on a plausible run; the warnings reach metrics.json, summary.md and back.
#include "harness/run/plausibility.h"

#include "geometry/input_error.h"
#include "harness/report/model_run_json.h"
#include "harness/report/run_report.h"
#include "harness/report/stability_report.h"
#include "models/json_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

using ::testing::HasSubstr;

constexpr double kDt = 1.0 / 60.0;

// The liver press's timing: the probe acts from 1.5 s, lets go at 3.0 s and is back up by
// 3.5 s; the run ends at 5.0 s.
scenes::Scene press_scene() {
  scenes::Scene scene;
  scene.name = "press";
  scene.dt = kDt;
  scene.duration = 5.0;
  scenes::Instrument instrument;
  instrument.path = {{0.0, Eigen::Vector3d(0.0, 0.0, 0.12), Eigen::Quaterniond::Identity()},
                     {2.5, Eigen::Vector3d(0.0, 0.0, -0.03), Eigen::Quaterniond::Identity()},
                     {3.0, Eigen::Vector3d(0.0, 0.0, -0.03), Eigen::Quaterniond::Identity()},
                     {3.5, Eigen::Vector3d(0.0, 0.0, 0.12), Eigen::Quaterniond::Identity()}};
  instrument.start = 1.5;
  instrument.release = 3.0;
  instrument.contact_margin = 2e-4;
  scene.instrument = instrument;
  return scene;
}

// A stable press on the liver as a plausible model reports it: a few percent of volume change,
// no tet inverted, the tool 2 cm in reading 0.4 N, nothing left on it once withdrawn.
ModelRun plausible_run() {
  ModelRun run;
  run.model = "plausible";
  run.vertices = 1215;
  run.tets = 4777;
  run.timing.steps_planned = run.timing.steps_run = 300;
  run.shape.volume_change = 0.07;
  run.shape.max_inverted_tets = 5;  // 0.1%: slivers under the probe
  run.shape.final_inverted_tets = 0;
  run.contact.max_penetration_pressing = 0.25e-3;  // within margin + 0.1 mm
  run.contact.peak_tool_force = 0.4;
  run.contact.loaded_travel = 0.02;
  for (int step = 0; step < 300; ++step) {
    StepSample sample;
    sample.time = (step + 1) * kDt;
    // Force while pressing and while the tissue follows the withdrawing tool up to 3.5 s.
    sample.tool_force = sample.time > 2.2 && sample.time < 3.4 ? 0.4 : 0.0;
    run.samples.push_back(sample);
  }
  return run;
}

std::vector<std::string> ids(const std::vector<Warning>& warnings) {
  std::vector<std::string> out;
  for (const Warning& warning : warnings) {
    out.push_back(warning.id);
  }
  return out;
}

// By value: callers pass the temporary judge_plausibility() returns.
Warning only(const std::vector<Warning>& warnings) {
  EXPECT_EQ(warnings.size(), 1u) << ::testing::PrintToString(ids(warnings));
  if (warnings.empty()) {
    throw std::logic_error("no warning");
  }
  return warnings.front();
}

TEST(Plausibility, APlausibleRunGetsNoWarning) {
  EXPECT_TRUE(judge_plausibility(plausible_run(), press_scene()).empty());
}

TEST(Plausibility, WarnsAboutAVolumeChangeNoTissueMakes) {
  ModelRun run = plausible_run();
  run.shape.volume_change = 9.44;
  const Warning warning = only(judge_plausibility(run, press_scene()));
  EXPECT_EQ(warning.id, kWarningVolumeChange);
  EXPECT_THAT(warning.message, HasSubstr("944%"));
  EXPECT_THAT(warning.message, HasSubstr("20%"));
  run.shape.volume_change = 0.2;  // at the limit: still plausible
  EXPECT_TRUE(judge_plausibility(run, press_scene()).empty());
}

TEST(Plausibility, WarnsWhenMoreThanOnePercentOfTheTetsInvertAtOnce) {
  ModelRun run = plausible_run();
  run.shape.max_inverted_tets = 48;  // 1.005%
  const Warning warning = only(judge_plausibility(run, press_scene()));
  EXPECT_EQ(warning.id, kWarningInvertedTets);
  EXPECT_THAT(warning.message, HasSubstr("48 tets"));
  EXPECT_THAT(warning.message, HasSubstr("of 4777"));
  run.shape.max_inverted_tets = 47;  // 0.98%
  EXPECT_TRUE(judge_plausibility(run, press_scene()).empty());
}

TEST(Plausibility, WarnsAboutTetsStillInvertedAtTheEnd) {
  ModelRun run = plausible_run();
  run.shape.final_inverted_tets = 2;
  const Warning warning = only(judge_plausibility(run, press_scene()));
  EXPECT_EQ(warning.id, kWarningStuckInverted);
  EXPECT_THAT(warning.message, HasSubstr("2 tets were still inverted at the end"));
  ASSERT_TRUE(stuck_inverted_warning(1).has_value());
  EXPECT_FALSE(stuck_inverted_warning(0).has_value());
}

TEST(Plausibility, WarnsAboutForceOnAWithdrawnToolButNotWhileItWithdraws) {
  const scenes::Scene scene = press_scene();
  EXPECT_DOUBLE_EQ(tool_withdrawn_time(scene), 3.5);  // the path ends after the release
  ModelRun run = plausible_run();
  // After the release at 3.0 s, while the tool goes back up, the tissue may still follow it.
  for (StepSample& sample : run.samples) {
    if (sample.time > 3.0 && sample.time <= 3.5) {
      sample.tool_force = 0.3;
    }
  }
  EXPECT_TRUE(judge_plausibility(run, scene).empty());
  // Once it is back up, nothing can hold on to it.
  run.samples.back().tool_force = 0.05;
  const Warning warning = only(judge_plausibility(run, scene));
  EXPECT_EQ(warning.id, kWarningForceAfterWithdrawal);
  EXPECT_THAT(warning.message, HasSubstr("0.05 N at 5 s"));
  EXPECT_THAT(warning.message, HasSubstr("withdrawn at 3.5 s"));
  // Below both thresholds (0.01 N, 1% of the peak): round-off, not a load.
  run.samples.back().tool_force = 0.009;
  EXPECT_TRUE(judge_plausibility(run, scene).empty());
  run.contact.peak_tool_force = 100.0;  // 1% of the peak is 1 N
  run.samples.back().tool_force = 0.5;
  EXPECT_TRUE(judge_plausibility(run, scene).empty());
}

TEST(Plausibility, ASceneGraspIsWithdrawnAtItsReleaseAndNoReleaseMeansNoCheck) {
  scenes::Scene scene;
  scene.dt = kDt;
  scenes::Grasp grasp;
  grasp.start = 1.0;
  grasp.release = 2.0;
  scene.grasp = grasp;
  EXPECT_DOUBLE_EQ(tool_withdrawn_time(scene), 2.0);
  ModelRun run = plausible_run();
  run.samples[150].tool_force = 0.2;  // t = 2.52 s
  EXPECT_EQ(only(judge_plausibility(run, scene)).id, kWarningForceAfterWithdrawal);
  scene.grasp->release = scenes::kNever;
  EXPECT_TRUE(judge_plausibility(run, scene).empty());
  EXPECT_EQ(tool_withdrawn_time(scenes::Scene{}), scenes::kNever);
}

TEST(Plausibility, WarnsAboutAToolThatWentInButReadNoForce) {
  ModelRun run = plausible_run();
  run.contact.peak_tool_force = 2e-6;
  for (StepSample& sample : run.samples) {
    sample.tool_force = std::min(sample.tool_force, 2e-6);
  }
  const Warning warning = only(judge_plausibility(run, press_scene()));
  EXPECT_EQ(warning.id, kWarningNoContactForce);
  EXPECT_THAT(warning.message, HasSubstr("went 20 mm into the tissue"));
  EXPECT_THAT(warning.message, HasSubstr("2e-06 N"));
  // A tool that never reached the tissue reads nothing, rightly.
  run.contact.loaded_travel = 0.5e-3;
  EXPECT_TRUE(judge_plausibility(run, press_scene()).empty());
}

TEST(Plausibility, WarnsAboutTissueDeeperInTheToolThanTheMarginAllows) {
  ModelRun run = plausible_run();
  run.contact.max_penetration_pressing = 3.69e-3;
  const Warning warning = only(judge_plausibility(run, press_scene()));
  EXPECT_EQ(warning.id, kWarningPenetration);
  EXPECT_THAT(warning.message, HasSubstr("3.69 mm into the tool"));
  EXPECT_THAT(warning.message, HasSubstr("0.2 mm margin"));
  run.contact.max_penetration_pressing = 0.29e-3;  // margin 0.2 mm + 0.1 mm
  EXPECT_TRUE(judge_plausibility(run, press_scene()).empty());
  scenes::Scene no_tool = press_scene();
  no_tool.instrument.reset();
  run.contact.max_penetration_pressing = 3.69e-3;
  EXPECT_TRUE(judge_plausibility(run, no_tool).empty());
}

TEST(Plausibility, WarnsAboutSolvesStoppedAtTheirIterationCap) {
  ModelRun run = plausible_run();
  run.solver.linear_solves = 300;
  run.solver.truncated_solves = 7;
  const Warning warning = only(judge_plausibility(run, press_scene()));
  EXPECT_EQ(warning.id, kWarningTruncatedSolves);
  EXPECT_THAT(warning.message, HasSubstr("7 of 300 linear solves stopped at their iteration cap"));
  run.solver.truncated_solves = 0;
  EXPECT_TRUE(judge_plausibility(run, press_scene()).empty());
}

TEST(Plausibility, WarnsAboutContactStepsThatRanOutOfPassesUnsettled) {
  scenes::Scene scene = press_scene();
  scene.instrument->contact_passes = 4;
  ModelRun run = plausible_run();
  run.contact.unsettled_steps = 12;
  const Warning warning = only(judge_plausibility(run, scene));
  EXPECT_EQ(warning.id, kWarningUnsettledContact);
  EXPECT_THAT(warning.message, HasSubstr("12 of 300 steps ran out of contact passes (4)"));
  run.contact.unsettled_steps = 0;
  EXPECT_TRUE(judge_plausibility(run, scene).empty());
}

TEST(Plausibility, ReportsEveryWarningOfARunInOrder) {
  ModelRun run = plausible_run();
  run.shape.volume_change = 5.76;
  run.shape.max_inverted_tets = 374;
  run.shape.final_inverted_tets = 3;
  run.samples.back().tool_force = 0.39;
  run.contact.max_penetration_pressing = 2.2e-3;
  run.contact.unsettled_steps = 3;
  run.solver.truncated_solves = 2;
  EXPECT_EQ(
      ids(judge_plausibility(run, press_scene())),
      (std::vector<std::string>{kWarningVolumeChange, kWarningInvertedTets, kWarningStuckInverted,
                                kWarningForceAfterWithdrawal, kWarningUnsettledContact,
                                kWarningPenetration, kWarningTruncatedSolves}));
}

TEST(Plausibility, ADivergedRunGetsNoneItsInstabilityIsTheFinding) {
  ModelRun run = plausible_run();
  run.shape.volume_change = 100.0;
  run.stability.stable = false;
  run.stability.diverged_at_step = 12;
  EXPECT_TRUE(judge_plausibility(run, press_scene()).empty());
}

TEST(Plausibility, LimitsAreTheOnesPassed) {
  ModelRun run = plausible_run();
  PlausibilityLimits strict;
  strict.max_volume_change = 0.05;
  EXPECT_EQ(only(judge_plausibility(run, press_scene(), strict)).id, kWarningVolumeChange);
}

// --- in metrics.json and summary.md ------------------------------------------------------------

TEST(PlausibilityReport, WarningsRoundTripThroughTheRunJsonAndTheReaderStaysStrict) {
  ModelRun run = plausible_run();
  run.shape.volume_change = 9.44;
  run.shape.final_inverted_tets = 3;
  run.contact.loaded_travel = 0.0123;
  run.warnings = judge_plausibility(run, press_scene());
  ASSERT_EQ(run.warnings.size(), 2u);
  run.contact.unsettled_steps = 5;  // after judging: the warnings stay the two above
  run.solver.truncated_solves = 4;
  const nlohmann::json json = nlohmann::json::parse(to_json(run).dump());
  EXPECT_EQ(json["warnings"][0]["id"], kWarningVolumeChange);
  EXPECT_EQ(json["shape"]["final_inverted_tets"], 3);
  EXPECT_EQ(json["contact"]["loaded_travel"], 0.0123);
  EXPECT_EQ(json["contact"]["unsettled_steps"], 5);
  EXPECT_EQ(json["solver"]["truncated_solves"], 4);
  const ModelRun back = model_run_from_json(JsonReader(json, "metrics.json"));
  ASSERT_EQ(back.warnings.size(), 2u);
  EXPECT_EQ(back.warnings[1].id, kWarningStuckInverted);
  EXPECT_EQ(back.warnings[1].message, run.warnings[1].message);
  EXPECT_EQ(back.shape.final_inverted_tets, 3);
  EXPECT_EQ(back.contact.loaded_travel, 0.0123);
  EXPECT_EQ(back.contact.unsettled_steps, 5);
  EXPECT_EQ(back.solver.truncated_solves, 4);
  EXPECT_EQ(to_json(back), json);

  nlohmann::json bad = json;
  bad["warnings"][0]["severity"] = "high";
  EXPECT_THROW(model_run_from_json(JsonReader(bad, "metrics.json")), InputError);
  bad = json;
  bad.erase("warnings");
  try {
    model_run_from_json(JsonReader(bad, "metrics.json"));
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("/warnings"));
  }
  bad = json;
  bad["warnings"][0].erase("message");
  EXPECT_THROW(model_run_from_json(JsonReader(bad, "metrics.json")), InputError);
}

TEST(PlausibilityReport, SummaryHasAWarningsColumnAndListsThemUnderTheTable) {
  ModelRun bad = plausible_run();
  bad.model = "shape_matching";
  bad.shape.volume_change = 9.44;
  bad.warnings = judge_plausibility(bad, press_scene());
  const std::string markdown = summary_markdown(press_scene(), {plausible_run(), bad});
  EXPECT_THAT(markdown, HasSubstr("| peak tool force (N) | warnings |"));
  EXPECT_THAT(markdown, HasSubstr("| 0.400 | none |"));
  EXPECT_THAT(markdown, HasSubstr("| 0.400 | volume_change |"));
  EXPECT_THAT(markdown, HasSubstr("- **shape_matching**: volume_change: the volume changed by up "
                                  "to 944%"));
  EXPECT_EQ(warnings_markdown({plausible_run()}), "");
  EXPECT_EQ(warnings_cell(plausible_run()), "none");
}

TEST(PlausibilityReport, StabilityFlagsATortureRunStuckInvertedAndOnlyThat) {
  StabilityReport report;
  report.scene = "bar";
  report.settings.time_steps = {0.01};
  ModelStability model;
  model.model = "mass_spring";
  TortureResult stuck;
  stuck.which = TortureCase::kSquash;
  stuck.run = true;
  stuck.verdict.final_inverted_tets = 3;
  stuck.verdict.max_inverted_tets = 40;
  TortureResult recovered = stuck;
  recovered.which = TortureCase::kStretch;
  recovered.verdict.final_inverted_tets = 0;  // inverted on the way: the torture, not a finding
  TortureResult diverged = stuck;
  diverged.which = TortureCase::kCollapse;
  diverged.verdict.status = RunStatus::kUnstable;
  model.torture = {stuck, recovered, diverged};
  report.models = {model};
  const std::string markdown = stability_markdown(report);
  EXPECT_THAT(markdown, HasSubstr("| wall (s) | warnings |"));
  EXPECT_THAT(markdown, HasSubstr("| 40 / 3 | - | - | 0.0 | stuck_inverted |"));
  EXPECT_THAT(markdown, HasSubstr("| 40 / 0 | - | - | 0.0 | none |"));
  const nlohmann::json json = stability_json(report);
  const nlohmann::json& torture = json["models"][0]["torture"];
  ASSERT_EQ(torture[0]["warnings"].size(), 1u);
  EXPECT_EQ(torture[0]["warnings"][0]["id"], kWarningStuckInverted);
  EXPECT_TRUE(torture[1]["warnings"].empty());
  EXPECT_TRUE(torture[2]["warnings"].empty());  // unstable: its instability is the finding
}

}  // namespace
}  // namespace softbench::harness
