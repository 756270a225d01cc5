// SPDX-License-Identifier: MIT
#include "harness/stability/stability.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_validation.h"
#include "harness/stability/torture_shapes.h"
#include "models/model_registry.h"
#include "scenes/scene_regions.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace softbench::harness {
namespace {

std::vector<double> halving_time_steps(double largest, int count) {
  std::vector<double> steps;
  for (int k = 0; k < count; ++k) {
    steps.push_back(largest / std::pow(2.0, k));
  }
  return steps;
}

int steps_for(double duration, double dt, int cap) {
  const double steps = std::ceil(duration / dt - 1e-9);
  return static_cast<int>(std::clamp(steps, 1.0, static_cast<double>(cap)));
}

// "1/60 s" for the halving steps, else seconds.
std::string time_step_seconds(double dt) {
  return time_step_label(dt) + " s";
}

std::string verdict_line(const RunVerdict& verdict) {
  std::ostringstream out;
  out << (verdict.status == RunStatus::kStable     ? "stable"
          : verdict.status == RunStatus::kUnstable ? "UNSTABLE (" + verdict.failure + ")"
                                                   : "TIMED OUT (" + verdict.failure + ")");
  if (std::isfinite(verdict.residual)) {
    out << ", " << (verdict.recovered() ? "recovered" : "NOT recovered") << " (residual "
        << std::setprecision(3) << 100.0 * verdict.residual << "%)";
  }
  out << ", max inverted tets " << verdict.max_inverted_tets << ", " << std::fixed
      << std::setprecision(1) << verdict.wall_seconds << " s";
  return out.str();
}

// The scene's loading, long enough to watch the recovery window after its release.
int loading_steps(const scenes::Scene& scene, const StabilitySettings& settings) {
  double duration = scene.duration;
  if (std::isfinite(scene.release_time())) {
    duration = std::max(duration, scene.release_time() + settings.recovery_window);
  }
  return steps_for(duration, scene.dt, settings.max_steps_per_run);
}

TortureResult run_case(TortureCase which,
                       const ModelInfo& info,
                       const scenes::Scene& scene,
                       const SceneMesh& scene_mesh,
                       const std::vector<int>& fixed,
                       const nlohmann::json& params,
                       const ParamSource& source,
                       const StabilitySettings& settings,
                       const RunBounds& bounds) {
  TortureResult result;
  result.which = which;
  const TetMesh& mesh = scene_mesh.body;
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  std::optional<Eigen::Matrix3Xd> tortured;
  switch (which) {
    case TortureCase::kSquash:
      tortured = squashed_to_plane(rest);
      result.note =
          "every vertex projected onto the plane through the centroid normal to the "
          "bounding box's shortest axis";
      break;
    case TortureCase::kCollapse: {
      tortured = collapsed_to_point(rest, settings.collapse_radius, settings.seed);
      std::ostringstream note;
      note << "every vertex moved to a random point (seed " << settings.seed
           << ") of a ball of radius " << settings.collapse_radius
           << " x the bbox diagonal around the centroid";
      result.note = note.str();
      break;
    }
    case TortureCase::kScramble: {
      tortured = scrambled(rest, settings.seed);
      std::ostringstream note;
      note << "every vertex moved to a random point (seed " << settings.seed
           << ") of the rest bounding box";
      result.note = note.str();
      break;
    }
    case TortureCase::kStretch: {
      tortured = stretched(rest, settings.stretch_factor);
      std::ostringstream note;
      note << "stretched " << settings.stretch_factor
           << "x along the bounding box's longest axis about the centroid";
      result.note = note.str();
      break;
    }
    case TortureCase::kIncompressible: {
      scenes::Scene changed = scene;
      changed.material.poisson_ratio = settings.incompressible_poisson;
      std::ostringstream note;
      note << "the scene's loading with Poisson's ratio " << settings.incompressible_poisson;
      result.note = note.str();
      const std::unique_ptr<SoftBody> body = info.create(mesh, changed.material, params, source);
      result.verdict =
          run_scene_loading(*body, changed, scene_mesh, loading_steps(changed, settings), bounds);
      result.run = true;
      break;
    }
    case TortureCase::kSliver: {
      std::vector<int> keep = fixed;
      const std::vector<int> grasped = scenes::grasped_vertices(scene, mesh);
      keep.insert(keep.end(), grasped.begin(), grasped.end());
      const std::optional<Sliver> sliver = flatten_one_tet(mesh, keep, settings.sliver_quality);
      if (!sliver) {
        result.note = "no tet could be flattened without inverting a neighbour";
        return result;
      }
      std::ostringstream note;
      note << "the scene's loading on the mesh with tet " << sliver->tet << " flattened (vertex "
           << sliver->vertex << " moved " << std::setprecision(3) << 1000.0 * sliver->moved
           << " mm toward its opposite face): radius ratio " << sliver->quality
           << ", worst other tet around that vertex " << sliver->neighbour_quality;
      result.note = note.str();
      SceneMesh sliver_mesh = scene_mesh;
      sliver_mesh.body = sliver->mesh;
      const std::unique_ptr<SoftBody> body =
          info.create(sliver_mesh.body, scene.material, params, source);
      result.verdict =
          run_scene_loading(*body, scene, sliver_mesh, loading_steps(scene, settings), bounds);
      result.run = true;
      break;
    }
  }
  if (tortured) {
    const std::unique_ptr<SoftBody> body = info.create(mesh, scene.material, params, source);
    result.verdict = run_torture(
        *body, mesh, fixed, *tortured, scene.dt,
        steps_for(settings.recovery_window, scene.dt, settings.max_steps_per_run), bounds);
    result.run = true;
  }
  result.recovered = result.verdict.recovered();
  return result;
}

const ModelStability* find_model(const std::vector<ModelStability>& models,
                                 const std::string& name) {
  for (const ModelStability& model : models) {
    if (model.model == name) {
      return &model;
    }
  }
  return nullptr;
}

}  // namespace

StiffnessAxis stiffness_axis(const std::string& model,
                             const std::vector<double>& young_moduli,
                             const std::vector<double>& unitless) {
  const StiffnessAxisSpec& spec = builtin_models().at(model).stiffness_axis;
  StiffnessAxis axis;
  axis.parameter = spec.parameter;
  axis.material = spec.material;
  axis.unit = spec.material ? "Pa" : "";
  axis.fixed_params = spec.fixed_params;
  axis.note = spec.note;
  axis.values = spec.material ? young_moduli : unitless;
  std::sort(axis.values.begin(), axis.values.end());
  return axis;
}

std::string torture_name(TortureCase which) {
  switch (which) {
    case TortureCase::kSquash:
      return "squash_to_plane";
    case TortureCase::kCollapse:
      return "collapse_to_point";
    case TortureCase::kScramble:
      return "scramble";
    case TortureCase::kStretch:
      return "stretch_3x";
    case TortureCase::kIncompressible:
      return "poisson_0.49";
    case TortureCase::kSliver:
      return "sliver_tet";
  }
  return "?";
}

bool is_large_deformation(TortureCase which) {
  return which == TortureCase::kSquash || which == TortureCase::kCollapse
         || which == TortureCase::kScramble || which == TortureCase::kStretch;
}

StabilitySettings default_stability_settings() {
  StabilitySettings settings;
  settings.young_moduli = {1e2, 1e3, 1e4, 1e5, 1e6};
  settings.unitless = {0.01, 0.0316, 0.1, 0.316, 1.0};
  settings.time_steps = halving_time_steps(1.0 / 30.0, 8);  // down to 1/3840 s
  return settings;
}

StabilitySettings quick_stability_settings() {
  StabilitySettings settings;
  settings.young_moduli = {1e3, 1e5};
  settings.unitless = {0.1, 1.0};
  settings.time_steps = halving_time_steps(1.0 / 30.0, 3);  // down to 1/120 s
  settings.map_duration = 0.25;
  settings.recovery_window = 2.0;
  settings.max_wall_seconds_per_run = 10.0;
  return settings;
}

std::string time_step_label(double dt) {
  std::ostringstream out;
  const double inverse = 1.0 / dt;
  if (std::abs(inverse - std::round(inverse)) < 1e-6 * inverse) {
    out << "1/" << std::llround(inverse);
  } else {
    out << dt;
  }
  return out.str();
}

MapRow scan_time_steps(double value,
                       const std::vector<double>& time_steps,
                       const std::function<RunVerdict(double dt)>& run) {
  MapRow row;
  row.value = value;
  bool done = false;
  for (const double dt : time_steps) {
    MapCell cell;
    cell.dt = dt;
    if (!done) {
      cell.verdict = run(dt);
      if (cell.verdict->status == RunStatus::kStable) {
        row.max_stable_dt = dt;
      }
      done = cell.verdict->status != RunStatus::kUnstable;
    }
    row.cells.push_back(cell);
  }
  return row;
}

ModelStability model_stability(const scenes::Scene& scene,
                               const SceneMesh& scene_mesh,
                               const std::string& model,
                               const StabilitySettings& settings,
                               std::ostream* progress) {
  const TetMesh& mesh = scene_mesh.body;
  const auto start = std::chrono::steady_clock::now();
  const ModelInfo& info = builtin_models().at(model);
  const ParamSource source{scene.source.string(), "/models/" + model};
  // A free body would fall through the map's runs (the displacement limit, not the dt, would
  // decide them) and need not return to its rest shape after a torture.
  const std::vector<int> fixed = scenes::required_fixed_vertices(
      scene, mesh, "stability",
      "its map hangs the body from it under gravity, and its torture cases let the body recover "
      "with it held");
  const RunBounds bounds{scene.limits, settings.max_wall_seconds_per_run};
  // The map hangs the body under gravity; a scene without gravity gets the usual one.
  const Eigen::Vector3d gravity = scene.gravity.acceleration.squaredNorm() > 0.0
                                      ? scene.gravity.acceleration
                                      : Eigen::Vector3d(0.0, 0.0, -9.81);

  ModelStability result;
  result.model = model;
  result.params = scene.parameters_for(model);
  result.axis = stiffness_axis(model, settings.young_moduli, settings.unitless);
  for (const double value : result.axis.values) {
    Material material = scene.material;
    nlohmann::json params = result.params;
    params.update(result.axis.fixed_params);
    if (result.axis.material) {
      material.young_modulus = value;
    } else {
      params[result.axis.parameter] = value;
      params.erase("calibrated");  // a fit of another stiffness no longer applies
    }
    result.map.push_back(scan_time_steps(value, settings.time_steps, [&](double dt) {
      const std::unique_ptr<SoftBody> body = info.create(mesh, material, params, source);
      return run_hanging(*body, mesh, fixed, gravity, dt,
                         steps_for(settings.map_duration, dt, settings.max_steps_per_run), bounds);
    }));
    if (progress != nullptr) {
      const MapRow& row = result.map.back();
      const bool timed_out = std::any_of(row.cells.begin(), row.cells.end(), [](const MapCell& c) {
        return c.is(RunStatus::kTimedOut);
      });
      *progress << model << ": " << result.axis.parameter << " = " << value
                << (result.axis.unit.empty() ? "" : " " + result.axis.unit) << ": max stable dt "
                << (row.max_stable_dt ? time_step_seconds(*row.max_stable_dt)
                    : timed_out       ? "unknown (a run timed out)"
                                      : "none")
                << "\n";
    }
  }
  for (const TortureCase which : settings.cases) {
    result.torture.push_back(
        run_case(which, info, scene, scene_mesh, fixed, result.params, source, settings, bounds));
    if (progress != nullptr) {
      const TortureResult& torture = result.torture.back();
      *progress << model << ": " << torture_name(which) << ": "
                << (torture.run ? verdict_line(torture.verdict) : "not run (" + torture.note + ")")
                << "\n";
    }
  }
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

std::vector<Claim> check_claims(const std::vector<ModelStability>& models,
                                const StabilitySettings& settings) {
  std::vector<Claim> claims;
  {
    Claim claim;
    claim.id = "shape_matching_unconditionally_stable";
    claim.claim = "Shape matching is unconditionally stable (thesis 3.3).";
    claim.criterion =
        "pass when every stability-map run (every alpha, from the largest dt down) and every "
        "torture case is stable: no NaN, no free vertex over the speed limit, no vertex past the "
        "displacement limit";
    if (const ModelStability* model = find_model(models, "shape_matching")) {
      int runs = 0;
      int by_displacement = 0;  // failures by the displacement limit alone: no NaN, no speed
      std::vector<std::string> failures;
      std::vector<std::string> timeouts;
      for (const MapRow& row : model->map) {
        for (const MapCell& cell : row.cells) {
          runs += cell.verdict.has_value();
          std::ostringstream where;
          where << "alpha " << row.value << " at dt " << time_step_seconds(cell.dt);
          if (cell.is(RunStatus::kUnstable)) {
            failures.push_back(where.str() + " (" + cell.verdict->failure + ")");
            by_displacement += cell.verdict->failure.rfind("displacement", 0) == 0;
          } else if (cell.is(RunStatus::kTimedOut)) {
            timeouts.push_back(where.str());
          }
        }
      }
      int cases = 0;
      for (const TortureResult& torture : model->torture) {
        cases += torture.run;
        if (torture.run && torture.verdict.status == RunStatus::kUnstable) {
          failures.push_back(torture_name(torture.which) + " (" + torture.verdict.failure + ")");
          by_displacement += torture.verdict.failure.rfind("displacement", 0) == 0;
        } else if (torture.run && torture.verdict.status == RunStatus::kTimedOut) {
          timeouts.push_back(torture_name(torture.which));
        }
      }
      claim.verdict = failures.empty() ? Verdict::kPass : Verdict::kFail;
      std::ostringstream evidence;
      if (failures.empty()) {
        evidence << "stable in all " << runs << " map runs (from the largest dt, "
                 << time_step_seconds(settings.time_steps.front()) << ", at every alpha) and all "
                 << cases << " torture cases";
      } else {
        if (by_displacement == static_cast<int>(failures.size())) {
          evidence << "never a NaN or a vertex over the speed limit, but all " << failures.size()
                   << " failures exceed the displacement limit (the body, hanging from its fixed "
                      "region, stretched or fell further than the limit: too soft at that alpha "
                      "and dt, not a numerical blow-up); ";
        }
        evidence << "unstable in:";
        for (const std::string& failure : failures) {
          evidence << " " << failure << (&failure == &failures.back() ? "" : ";");
        }
      }
      if (!timeouts.empty()) {
        evidence << "; timed out (not shown either way):";
        for (const std::string& timeout : timeouts) {
          evidence << " " << timeout;
        }
      }
      claim.evidence = evidence.str();
    } else {
      claim.evidence = "shape_matching was not run";
    }
    claims.push_back(claim);
  }
  {
    Claim claim;
    claim.id = "mass_spring_may_fail_at_large_deformation";
    claim.claim = "Mass-spring may fail at large deformation (thesis 3.5.2).";
    claim.criterion =
        "observed when some large-deformation torture case (squash, collapse, scramble, stretch) "
        "diverges or ends its recovery at a residual of 1% of the bounding-box diagonal or more; "
        "a possibility, so not observed is no failure";
    if (const ModelStability* model = find_model(models, "mass_spring")) {
      std::vector<std::string> failed;
      std::vector<std::string> survived;
      for (const TortureResult& torture : model->torture) {
        if (!torture.run || !is_large_deformation(torture.which)) {
          continue;
        }
        std::ostringstream line;
        line << torture_name(torture.which);
        if (!torture.verdict.stable()) {
          line << " (" << torture.verdict.failure << ")";
          failed.push_back(line.str());
        } else if (!torture.recovered) {
          line << " (residual " << std::setprecision(3) << 100.0 * torture.verdict.residual
               << "% after " << settings.recovery_window << " s)";
          failed.push_back(line.str());
        } else {
          survived.push_back(line.str());
        }
      }
      if (failed.empty() && survived.empty()) {
        claim.evidence = "no large-deformation torture case was run";
      } else {
        claim.verdict = failed.empty() ? Verdict::kNotObserved : Verdict::kObserved;
        std::ostringstream evidence;
        evidence << "fails to recover from:";
        for (const std::string& item : failed) {
          evidence << " " << item << (&item == &failed.back() ? "" : ";");
        }
        if (failed.empty()) {
          evidence << " none";
        }
        evidence << "; recovers from:";
        for (const std::string& item : survived) {
          evidence << " " << item << (&item == &survived.back() ? "" : ",");
        }
        if (survived.empty()) {
          evidence << " none";
        }
        claim.evidence = evidence.str();
      }
    } else {
      claim.evidence = "mass_spring was not run";
    }
    claims.push_back(claim);
  }
  return claims;
}

StabilityReport run_stability(const scenes::Scene& scene, const StabilityOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> names =
      options.models.empty() ? builtin_models().default_names() : options.models;
  for (const std::string& name : names) {
    try {
      builtin_models().at(name);  // an unknown name fails before any model runs
    } catch (const InputError& error) {
      throw InputError("--model " + name + ": " + error.what());
    }
  }
  const SceneMesh mesh = read_scene_mesh(scene);
  StabilityReport report;
  report.scene = scene.name;
  report.scene_file = scene.source.string();
  report.vertices = mesh.body.num_vertices();
  report.tets = mesh.body.num_tets();
  report.scene_dt = scene.dt;
  report.settings = options.settings;
  for (const std::string& name : names) {
    report.models.push_back(model_stability(scene, mesh, name, options.settings, options.progress));
  }
  report.claims = check_claims(report.models, options.settings);
  report.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace softbench::harness
