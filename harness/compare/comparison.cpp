// SPDX-License-Identifier: MIT
#include "harness/compare/comparison.h"

#include "geometry/input_error.h"
#include "harness/calibrate/calibration.h"
#include "harness/format.h"
#include "harness/provenance.h"
#include "harness/run/reference.h"
#include "models/model_registry.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <utility>

namespace softbench::harness {
namespace {

/// The tables' percentages: two digits after the point, so a column lines up.
std::string percent_2(double fraction) {
  return fixed(100.0 * fraction, 2) + "%";
}

std::string seconds(double value) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(2) << value << " s";
  return out.str();
}

const ModelRun* find_run(const SceneComparison& scene, std::string_view label) {
  for (const ModelRun& run : scene.runs) {
    if (run.model == label) {
      return &run;
    }
  }
  return nullptr;
}

std::string instability(const ModelRun& run) {
  return "diverged at step "
         + (run.stability.diverged_at_step ? std::to_string(*run.stability.diverged_at_step) : "?")
         + " (" + run.stability.divergence + ")";
}

bool recovered(const ModelRun& run) {
  return run.stability.stable && run.recovery.measured
         && run.recovery.residual < kRecoveredResidual;
}

// "residual 0.31% (below 1% after 0.42 s)" or "no release".
std::string recovery_evidence(const ModelRun& run) {
  if (!run.stability.stable) {
    return instability(run);
  }
  if (!run.recovery.measured) {
    return "nothing released";
  }
  return "residual " + percent_2(run.recovery.residual)
         + (run.recovery.time_to_one_percent
                ? " (below 1% " + seconds(*run.recovery.time_to_one_percent) + " after the release)"
                : " (never below 1% for good)");
}

std::string shape_evidence(const ModelRun& run) {
  return std::to_string(run.shape.max_inverted_tets) + " inverted tets, max volume change "
         + percent_2(run.shape.volume_change);
}

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
  std::string joined;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    joined += (i == 0 ? "" : separator) + parts[i];
  }
  return joined;
}

Claim shape_matching_claim(const std::vector<SceneComparison>& scenes,
                           const ClaimCriteria& criteria) {
  Claim check;
  check.id = "shape_matching_recovers_without_distortion";
  check.claim =
      "Shape matching recovers its shape after every deformation, without visible distortion "
      "(thesis 3.5.2, Fig. 3.14).";
  check.criterion = "on every scene: stable, at most " + std::to_string(criteria.max_inverted_tets)
                    + " inverted tets at any step, and after the release an RMS residual below "
                    + percent_2(kRecoveredResidual) + " of the rest bounding-box diagonal";
  std::vector<std::string> evidence;
  bool ran = false;
  bool any_release = false;
  bool failed = false;
  for (const SceneComparison& scene : scenes) {
    const ModelRun* run = find_run(scene, "shape_matching");
    if (run == nullptr) {
      continue;
    }
    ran = true;
    any_release = any_release || run->recovery.measured;
    const bool distorted = run->shape.max_inverted_tets > criteria.max_inverted_tets;
    const bool fine =
        run->stability.stable && !distorted && (!run->recovery.measured || recovered(*run));
    failed = failed || !fine;
    evidence.push_back(scene.name + ": " + recovery_evidence(*run) + ", " + shape_evidence(*run));
  }
  if (!ran) {
    check.verdict = Verdict::kNotRun;
    check.evidence = "shape_matching was not run";
  } else if (failed) {
    check.verdict = Verdict::kFail;
  } else {
    check.verdict = any_release ? Verdict::kPass : Verdict::kNotRun;
    if (!any_release) {
      evidence.push_back("no scene releases a load, so recovery was not measured");
    }
  }
  if (ran) {
    check.evidence = join(evidence, "; ");
  }
  return check;
}

Claim mass_spring_claim(const std::vector<SceneComparison>& scenes) {
  Claim check;
  check.id = "mass_spring_may_not_recover";
  check.claim =
      "The mass-spring model may deform unrealistically and fail to recover from a large "
      "deformation (thesis 3.5.2, Fig. 3.15).";
  check.criterion = "observed when on some scene it diverges or ends its recovery with an RMS "
                    "residual of "
                    + percent_2(kRecoveredResidual)
                    + " of the bounding-box diagonal or more; a possibility, so not observed is "
                      "no failure";
  std::vector<std::string> evidence;
  bool ran = false;
  bool any_release = false;
  bool observed = false;
  for (const SceneComparison& scene : scenes) {
    const ModelRun* run = find_run(scene, "mass_spring");
    if (run == nullptr) {
      continue;
    }
    ran = true;
    any_release = any_release || run->recovery.measured || !run->stability.stable;
    observed = observed || !run->stability.stable || (run->recovery.measured && !recovered(*run));
    evidence.push_back(scene.name + ": " + recovery_evidence(*run) + ", " + shape_evidence(*run));
  }
  if (!ran) {
    check.verdict = Verdict::kNotRun;
    check.evidence = "mass_spring was not run";
    return check;
  }
  if (observed) {
    check.verdict = Verdict::kObserved;
  } else if (any_release) {
    check.verdict = Verdict::kNotObserved;
  } else {
    check.verdict = Verdict::kNotRun;
    evidence.push_back("no scene releases a load, so recovery was not measured");
  }
  check.evidence = join(evidence, "; ");
  return check;
}

Claim linear_fem_claim(const std::vector<SceneComparison>& scenes, const ClaimCriteria& criteria) {
  Claim check;
  check.id = "linear_fem_unfit_corotational_fit";
  check.claim =
      "FEM built on the small-deformation assumption (linear FEM) is unfit for large deformation "
      "(thesis 3.5.2), while corotational FEM, which factors out element rotations, is fit.";
  std::ostringstream criterion;
  criterion << "corotational_fem fit on every scene: stable, at most " << criteria.max_inverted_tets
            << " inverted tets, recovered below " << percent_2(kRecoveredResidual)
            << " where released; corotational_fem(linear) unfit on at least one: diverged, more "
               "inverted tets than corotational, not recovered, or a volume change more than "
            << criteria.volume_ratio << "x corotational's and at least "
            << percent_2(criteria.volume_margin) << " more";
  check.criterion = criterion.str();
  std::vector<std::string> evidence;
  bool ran = false;
  bool corotational_fit = true;
  bool linear_unfit = false;
  for (const SceneComparison& scene : scenes) {
    const ModelRun* corotational = find_run(scene, "corotational_fem");
    const ModelRun* linear = find_run(scene, "corotational_fem(linear)");
    if (corotational == nullptr || linear == nullptr) {
      continue;
    }
    ran = true;
    corotational_fit = corotational_fit && corotational->stability.stable
                       && corotational->shape.max_inverted_tets <= criteria.max_inverted_tets
                       && (!corotational->recovery.measured || recovered(*corotational));
    const bool inflated =
        linear->shape.volume_change > criteria.volume_ratio * corotational->shape.volume_change
        && linear->shape.volume_change - corotational->shape.volume_change
               >= criteria.volume_margin;
    linear_unfit = linear_unfit || !linear->stability.stable
                   || (corotational->stability.stable
                       && linear->shape.max_inverted_tets > corotational->shape.max_inverted_tets)
                   || (linear->recovery.measured && !recovered(*linear)) || inflated;
    evidence.push_back(scene.name + ": linear " + recovery_evidence(*linear) + ", "
                       + shape_evidence(*linear) + " vs corotational "
                       + recovery_evidence(*corotational) + ", " + shape_evidence(*corotational));
  }
  if (!ran) {
    check.verdict = Verdict::kNotRun;
    check.evidence = "needs both corotational_fem and corotational_fem(linear) on the same scene";
    return check;
  }
  check.verdict = corotational_fit && linear_unfit ? Verdict::kPass : Verdict::kFail;
  check.evidence = join(evidence, "; ");
  return check;
}

}  // namespace

const std::vector<ModelVariant>& known_variants() {
  static const std::vector<ModelVariant> variants{
      {"corotational_fem(linear)", "corotational_fem", {{"formulation", "linear"}}},
  };
  return variants;
}

std::vector<ModelVariant> resolve_models(const std::vector<std::string>& names) {
  const ModelRegistry& registry = builtin_models();
  std::vector<ModelVariant> rows;
  if (names.empty()) {
    for (const std::string& name : registry.default_names()) {
      rows.push_back({name, name, nlohmann::json::object()});
      for (const ModelVariant& variant : known_variants()) {
        if (variant.model == name) {
          rows.push_back(variant);
        }
      }
    }
    return rows;
  }
  for (const std::string& name : names) {
    const auto variant = std::find_if(known_variants().begin(), known_variants().end(),
                                      [&](const ModelVariant& v) { return v.label == name; });
    if (variant != known_variants().end()) {
      registry.at(variant->model);  // InputError when this build leaves the base model out
      rows.push_back(*variant);
    } else if (registry.contains(name)) {
      rows.push_back({name, name, nlohmann::json::object()});
    } else {
      std::vector<std::string> known = registry.names();
      for (const ModelVariant& v : known_variants()) {
        known.push_back(v.label);
      }
      throw InputError("--model " + name + ": unknown model (known: " + join(known, ", ") + ")");
    }
  }
  return rows;
}

std::optional<double> thesis_steps_per_second(std::string_view label) {
  // Frames per second in the thesis's figures 3.11-3.13: one simulation step per frame.
  static const std::map<std::string, double, std::less<>> figures{
      {"mass_spring", 335.7},
      {"corotational_fem", 36.5},
      {"corotational_fem(linear)", 36.5},
      {"shape_matching", 787.0},
  };
  const auto found = figures.find(label);
  return found == figures.end() ? std::nullopt : std::optional<double>(found->second);
}

std::vector<Claim> check_claims(const std::vector<SceneComparison>& scenes,
                                const ClaimCriteria& criteria) {
  return {shape_matching_claim(scenes, criteria), mass_spring_claim(scenes),
          linear_fem_claim(scenes, criteria)};
}

std::vector<SpeedRatio> speed_ratios(const std::vector<ModelRun>& runs) {
  const auto rate = [&](std::string_view label) -> std::optional<double> {
    for (const ModelRun& run : runs) {
      if (run.model == label && run.stability.stable
          && run.timing.steps_per_second_with_collision > 0.0) {
        return run.timing.steps_per_second_with_collision;
      }
    }
    return std::nullopt;
  };
  const std::optional<double> fem = rate("corotational_fem");
  std::vector<SpeedRatio> ratios;
  for (const char* label : {"shape_matching", "mass_spring"}) {
    SpeedRatio ratio{label,
                     *thesis_steps_per_second(label) / *thesis_steps_per_second("corotational_fem"),
                     std::nullopt};
    const std::optional<double> ours = rate(label);
    if (fem && ours) {
      ratio.ours = *ours / *fem;
    }
    ratios.push_back(ratio);
  }
  return ratios;
}

namespace {

/// Table B for one scene: each row matched to the tissue and measured against `reference`.
MatchedScene run_matched(const scenes::Scene& scene,
                         const SceneMesh& mesh,
                         const std::vector<ModelVariant>& rows,
                         const ReferenceSettings& settings,
                         const ReferenceRun& reference,
                         const CompareOptions& options) {
  MatchedScene matched;
  matched.name = scene.name;
  matched.reference = settings.model;
  CalibrationOptions calibration_options;
  calibration_options.against = settings.model;
  calibration_options.cache_dir = options.calibration_dir;
  for (const ModelVariant& row : rows) {
    scenes::Scene row_scene = scene;
    if (!row.overrides.empty()) {
      row_scene.override_parameters(row.model, row.overrides);
    }
    if (calibratable(row.model)) {
      if (options.progress != nullptr) {
        *options.progress << scene.name << " / " << row.label << ": calibrating to "
                          << settings.model << "\n";
      }
      try {
        const Calibration calibration = calibrate(row_scene, mesh, row.model, calibration_options);
        row_scene.model_parameters[row.model] = calibration.params;
        matched.calibrations[row.label] = {
            {"values", calibration.values},   {"targets", calibration.targets},
            {"errors", calibration.errors},   {"evaluations", calibration.evaluations},
            {"seconds", calibration.seconds}, {"cached", calibration.cached}};
      } catch (const InputError& error) {
        matched.notes.push_back(row.label + ": not calibrated, run with the scene's block ("
                                + error.what() + ")");
      }
    }
    RunOptions run_options;
    run_options.models = {row.model};
    run_options.warmup_steps = options.warmup_steps;
    run_options.snapshot_times = comparison_times(scene, settings.times);
    run_options.picture_times = picture_times(scene);
    if (options.progress != nullptr) {
      *options.progress << scene.name << " / " << row.label << " (matched):\n";
    }
    run_options.progress = options.progress;
    run_options.live_progress = options.live_progress;
    for (ModelRun& run : run_scene(row_scene, mesh, run_options)) {
      run.model = row.label;
      run.accuracy = accuracy_against(run.snapshots, run.contact.peak_tool_force, reference,
                                      mesh.body.rest_positions());
      run.snapshots.clear();  // measured; the report keeps the errors, not the shapes
      matched.runs.push_back(std::move(run));
    }
  }
  return matched;
}

}  // namespace

Comparison run_comparison(const std::vector<scenes::Scene>& scenes, const CompareOptions& options) {
  const std::vector<ModelVariant> rows = resolve_models(options.models);
  Comparison comparison;
  // The thread count beside the CPU: the models that use OpenMP threads (the corotational FEM
  // from 2048 vertices, step by step as they are faster) get this many.
  const Provenance machine = provenance();
  comparison.machine = machine.cpu + " with " + std::to_string(machine.threads) + " OpenMP thread"
                       + (machine.threads == 1 ? "" : "s");
  for (const scenes::Scene& scene : scenes) {
    SceneComparison result;
    result.name = scene.name;
    const SceneMesh mesh = read_scene_mesh(scene);
    for (const ModelVariant& row : rows) {
      scenes::Scene variant_scene = scene;
      if (!row.overrides.empty()) {
        variant_scene.override_parameters(row.model, row.overrides);
      }
      RunOptions run_options;
      run_options.models = {row.model};
      run_options.warmup_steps = options.warmup_steps;
      run_options.picture_times = picture_times(scene);
      run_options.progress = options.progress;
      run_options.live_progress = options.live_progress;
      if (options.progress != nullptr) {
        *options.progress << scene.name << " / " << row.label << ":\n";
      }
      std::vector<ModelRun> runs = run_scene(variant_scene, mesh, run_options);
      for (ModelRun& run : runs) {
        run.model = row.label;
        result.runs.push_back(std::move(run));
      }
    }
    result.scene = scenes::to_json(scene);
    comparison.scenes.push_back(std::move(result));
    if (options.matched) {
      const ReferenceSettings settings;
      if (options.progress != nullptr) {
        *options.progress << scene.name << ": the reference (" << settings.model << ", dt / "
                          << settings.substeps << ") for table B\n";
      }
      try {
        const ReferenceRun reference = reference_run(scene, mesh, settings, options.reference_dir);
        comparison.matched.push_back(run_matched(scene, mesh, rows, settings, reference, options));
        const bool presses = scene.instrument && !scene.instrument->grasp && !scene.grasp;
        if (options.equal_accuracy && presses && !comparison.equal_accuracy) {
          EqualAccuracyOptions trade;
          for (const ModelVariant& row : rows) {
            if (row.overrides.empty()) {
              trade.models.push_back(row.model);
            }
          }
          trade.calibration_dir = options.calibration_dir;
          trade.reference_model = settings.model;
          trade.warmup_steps = options.warmup_steps;
          trade.progress = options.progress;
          comparison.equal_accuracy = run_equal_accuracy(scene, mesh, reference, trade);
        }
      } catch (const InputError& error) {
        MatchedScene unmatched;
        unmatched.name = scene.name;
        unmatched.reference = settings.model;
        unmatched.notes.push_back(std::string("no reference: ") + error.what());
        comparison.matched.push_back(std::move(unmatched));
      }
    }
  }
  if (comparison.matched.empty()) {
    comparison.claims = check_claims(comparison.scenes, comparison.criteria);
  } else {
    std::vector<SceneComparison> judged;
    for (const MatchedScene& scene : comparison.matched) {
      judged.push_back({scene.name, nlohmann::json::object(), scene.runs});
    }
    comparison.claims = check_claims(judged, comparison.criteria);
  }
  return comparison;
}

}  // namespace softbench::harness
