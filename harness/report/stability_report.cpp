// SPDX-License-Identifier: MIT
#include "harness/report/stability_report.h"

#include "harness/format.h"
#include "harness/report/report_files.h"
#include "harness/provenance.h"
#include "harness/report/run_report.h"
#include "harness/run/plausibility.h"

#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

namespace softbench::harness {
namespace {

nlohmann::json verdict_json(const RunVerdict& verdict) {
  return {
      {"status", to_string(verdict.status)},
      {"nan", verdict.nan},
      {"failure", verdict.failure},
      {"diverged_at_step", verdict.diverged_at_step >= 0 ? nlohmann::json(verdict.diverged_at_step)
                                                         : nlohmann::json(nullptr)},
      {"steps_planned", verdict.steps_planned},
      {"steps_run", verdict.steps_run},
      {"wall_seconds", verdict.wall_seconds},
      {"max_inverted_tets", verdict.max_inverted_tets},
      {"final_inverted_tets", verdict.final_inverted_tets},
      {"residual", number_or_null(verdict.residual)},
      {"settled_after_s",
       verdict.settled_after ? nlohmann::json(*verdict.settled_after) : nlohmann::json(nullptr)},
      {"time_to_one_percent_s", verdict.time_to_one_percent
                                    ? nlohmann::json(*verdict.time_to_one_percent)
                                    : nlohmann::json(nullptr)}};
}

// The plausibility checks a stability run can be judged by: it knows its inverted-tet counts,
// not its volume or its tool (the map's runs hang under gravity; the shape tortures start from
// a shape no tissue takes, so inverted tets during the run are the test, not a finding). A
// stable run still inverted at the end is stuck inverted.
std::vector<Warning> verdict_warnings(const RunVerdict& verdict) {
  std::vector<Warning> warnings;
  if (verdict.stable()) {
    if (std::optional<Warning> stuck = stuck_inverted_warning(verdict.final_inverted_tets)) {
      warnings.push_back(*stuck);
    }
  }
  return warnings;
}

std::string map_cell_text(const MapRow& row) {
  if (row.max_stable_dt) {
    std::string text = time_step_label(*row.max_stable_dt);
    for (const MapCell& cell : row.cells) {
      if (cell.is(RunStatus::kStable) && cell.verdict->max_inverted_tets > 0) {
        text += " (" + std::to_string(cell.verdict->max_inverted_tets) + " inv.)";
      }
    }
    return text;
  }
  for (const MapCell& cell : row.cells) {
    if (cell.is(RunStatus::kTimedOut)) {
      return "timed out at " + time_step_label(cell.dt);
    }
  }
  return "none";
}

}  // namespace

nlohmann::json stability_json(const StabilityReport& report) {
  const StabilitySettings& settings = report.settings;
  nlohmann::json json;
  json["provenance"] = to_json(provenance());
  json["scene"] = {{"name", report.scene},
                   {"file", report.scene_file},
                   {"mesh", {{"vertices", report.vertices}, {"tets", report.tets}}},
                   {"dt", report.scene_dt}};
  nlohmann::json cases = nlohmann::json::array();
  for (const TortureCase which : settings.cases) {
    cases.push_back(torture_name(which));
  }
  json["settings"] = {{"time_steps", settings.time_steps},
                      {"young_moduli", settings.young_moduli},
                      {"unitless", settings.unitless},
                      {"map_duration_s", settings.map_duration},
                      {"cases", cases},
                      {"recovery_window_s", settings.recovery_window},
                      {"recovered_below", kRecoveredResidual},
                      {"stretch_factor", settings.stretch_factor},
                      {"collapse_radius", settings.collapse_radius},
                      {"incompressible_poisson", settings.incompressible_poisson},
                      {"sliver_quality", settings.sliver_quality},
                      {"seed", settings.seed},
                      {"max_steps_per_run", settings.max_steps_per_run},
                      {"max_wall_seconds_per_run", settings.max_wall_seconds_per_run}};
  json["models"] = nlohmann::json::array();
  for (const ModelStability& model : report.models) {
    nlohmann::json entry;
    entry["model"] = model.model;
    entry["params"] = model.params;
    entry["axis"] = {{"parameter", model.axis.parameter}, {"unit", model.axis.unit},
                     {"material", model.axis.material},   {"fixed_params", model.axis.fixed_params},
                     {"values", model.axis.values},       {"note", model.axis.note}};
    entry["map"] = nlohmann::json::array();
    for (const MapRow& row : model.map) {
      nlohmann::json cells = nlohmann::json::array();
      for (const MapCell& cell : row.cells) {
        nlohmann::json item = {
            {"dt", cell.dt},
            {"status", cell.verdict ? to_string(cell.verdict->status) : "not_run"}};
        if (cell.verdict) {
          item["verdict"] = verdict_json(*cell.verdict);
        }
        cells.push_back(item);
      }
      entry["map"].push_back(
          {{"value", row.value},
           {"max_stable_dt",
            row.max_stable_dt ? nlohmann::json(*row.max_stable_dt) : nlohmann::json(nullptr)},
           {"cells", cells}});
    }
    entry["torture"] = nlohmann::json::array();
    for (const TortureResult& torture : model.torture) {
      nlohmann::json item = {
          {"case", torture_name(torture.which)}, {"run", torture.run}, {"note", torture.note}};
      if (torture.run) {
        item["stable"] = torture.verdict.stable();
        item["recovered"] = torture.recovered;
        item["nan"] = torture.verdict.nan;
        item["verdict"] = verdict_json(torture.verdict);
        item["warnings"] = nlohmann::json::array();
        for (const Warning& warning : verdict_warnings(torture.verdict)) {
          item["warnings"].push_back({{"id", warning.id}, {"message", warning.message}});
        }
      }
      entry["torture"].push_back(item);
    }
    entry["wall_seconds"] = model.wall_seconds;
    json["models"].push_back(entry);
  }
  json["claims"] = nlohmann::json::array();
  for (const Claim& claim : report.claims) {
    json["claims"].push_back(to_json(claim));
  }
  json["wall_seconds"] = report.wall_seconds;
  return json;
}

std::string stability_markdown(const StabilityReport& report) {
  const StabilitySettings& settings = report.settings;
  std::ostringstream out;
  out << "# Stability at the extremes: " << report.scene << "\n\n";
  out << "Scene " << report.scene_file << ", " << report.vertices << " vertices, " << report.tets
      << " tets. A run is **stable** when no NaN/Inf appears, every free vertex stays under the "
         "scene's speed limit and every vertex within its displacement limit of rest; every run "
         "is bounded by "
      << settings.max_steps_per_run << " steps and " << settings.max_wall_seconds_per_run
      << " s of wall time (a run over it is *timed out*, neither stable nor unstable); a "
         "recovery ends early once every free vertex has been slower than 1e-4 bbox diagonals/s "
         "for 10 steps (settled). Took "
      << fixed(report.wall_seconds, 1) << " s.\n\n";

  out << "## The thesis's claims\n\n";
  for (const Claim& claim : report.claims) {
    out << claim_markdown(claim);
  }

  out << "\n## Largest stable time step (s)\n\n"
      << "Each run: " << settings.map_duration
      << " s of simulated time, the scene's fixed region held and gravity on, from rest. Time "
         "steps are tried from "
      << time_step_label(settings.time_steps.front()) << " s down to "
      << time_step_label(settings.time_steps.back())
      << " s, halving, and the scan stops at the first stable one (\"none\": unstable at every "
         "one; \"inv.\": tets inverted during the stable run).\n\n";
  // One table per axis (the material's E, or a model's own unitless stiffness).
  std::map<std::string, std::vector<const ModelStability*>> by_axis;
  std::vector<std::string> axis_order;
  for (const ModelStability& model : report.models) {
    // Models on the material's E share a table; a model's own stiffness gets its own.
    const std::string key = model.axis.material ? std::string("young_modulus") : model.model;
    if (by_axis.find(key) == by_axis.end()) {
      axis_order.push_back(key);
    }
    by_axis[key].push_back(&model);
  }
  for (const std::string& key : axis_order) {
    const std::vector<const ModelStability*>& models = by_axis[key];
    const StiffnessAxis& axis = models.front()->axis;
    out << "| model | axis |";
    for (const double value : axis.values) {
      out << " " << (axis.material ? "E = " : axis.parameter + " = ") << value
          << (axis.unit.empty() ? "" : " " + axis.unit) << " |";
    }
    out << "\n|---|---|";
    for (std::size_t i = 0; i < axis.values.size(); ++i) {
      out << "---|";
    }
    out << "\n";
    for (const ModelStability* model : models) {
      out << "| " << model->model << " | " << model->axis.note << " |";
      for (const MapRow& row : model->map) {
        out << " " << map_cell_text(row) << " |";
      }
      out << "\n";
    }
    out << "\n";
  }

  out << "## Torture cases\n\n"
      << "Shape tortures (squash, collapse, scramble, stretch): every vertex is placed on the "
         "tortured shape by exact position constraints for one step and held there one more "
         "(so the body starts from rest), then released with only the fixed region held (at "
         "rest) and no gravity for "
      << settings.recovery_window << " s at the scene's dt (" << time_step_label(report.scene_dt)
      << " s). The other two run the scene's own loading, extended to " << settings.recovery_window
      << " s after its release. **Recovered**: stable and the RMS distance to the shape "
         "recovered toward (rest; for the scene runs, the scene's reference shape) is below "
      << percent(kRecoveredResidual)
      << " of the bounding-box diagonal at the end. Inverted tets: the most over the steps "
         "the model moved the body, and how many were still inverted at the end. Warnings: the "
         "plausibility checks (harness/run/plausibility.h) a torture run can be judged by; it "
         "knows only its inverted tets, so only a stable run stuck inverted at the end "
         "(stuck_inverted) is flagged.\n\n";
  out << "| model | case | stable | recovered | NaN | inverted tets (max / at the end) | final "
         "residual | time to 1% (s) | wall (s) | warnings |\n"
         "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ModelStability& model : report.models) {
    for (const TortureResult& torture : model.torture) {
      out << "| " << model.model << " | " << torture_name(torture.which) << " | ";
      if (!torture.run) {
        out << "not run | - | - | - | - | - | - | - |\n";
        continue;
      }
      const RunVerdict& verdict = torture.verdict;
      out << (verdict.status == RunStatus::kStable ? "yes"
              : verdict.status == RunStatus::kUnstable
                  ? "**NO** (step " + std::to_string(verdict.diverged_at_step) + ": "
                        + verdict.failure + ")"
                  : "timed out")
          << " | " << (torture.recovered ? "yes" : "**no**") << " | "
          << (verdict.nan ? "**yes**" : "no") << " | " << verdict.max_inverted_tets << " / "
          << verdict.final_inverted_tets << " | "
          << (std::isfinite(verdict.residual) ? percent(verdict.residual) : "-") << " | ";
      std::string warnings;
      for (const Warning& warning : verdict_warnings(verdict)) {
        warnings += (warnings.empty() ? "" : ", ") + warning.id;
      }
      out << (verdict.time_to_one_percent ? fixed(*verdict.time_to_one_percent, 2) : "-") << " | "
          << fixed(verdict.wall_seconds, 1) << " | " << (warnings.empty() ? "none" : warnings)
          << " |\n";
    }
  }
  out << "\nHow each case was set up:\n\n";
  std::map<std::string, std::string> notes;
  for (const ModelStability& model : report.models) {
    for (const TortureResult& torture : model.torture) {
      notes.emplace(torture_name(torture.which), torture.note);
    }
  }
  for (const auto& [name, note] : notes) {
    out << "- " << name << ": " << note << "\n";
  }
  return out.str();
}

void write_stability(const std::filesystem::path& out_dir, const StabilityReport& report) {
  write_report_files(out_dir, {{"stability.json", stability_json(report).dump(2) + "\n"},
                               {"stability.md", stability_markdown(report)}});
}

}  // namespace softbench::harness
