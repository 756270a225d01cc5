// SPDX-License-Identifier: MIT
#include "harness/report/run_report.h"

#include "harness/report/report_files.h"
#include "harness/provenance.h"
#include "harness/report/model_run_json.h"

#include <iomanip>
#include <sstream>

namespace softbench::harness {

nlohmann::json metrics_json(const scenes::Scene& scene, const std::vector<ModelRun>& runs) {
  nlohmann::json json;
  json["provenance"] = to_json(provenance());
  json["scene"] = scenes::to_json(scene);
  json["runs"] = nlohmann::json::array();
  for (const ModelRun& run : runs) {
    json["runs"].push_back(to_json(run));
  }
  return json;
}

std::string warnings_cell(const ModelRun& run) {
  if (run.warnings.empty()) {
    return "none";
  }
  std::string cell;
  for (const Warning& warning : run.warnings) {
    cell += (cell.empty() ? "" : ", ") + warning.id;
  }
  return cell;
}

std::string warnings_markdown(const std::vector<ModelRun>& runs) {
  std::ostringstream out;
  for (const ModelRun& run : runs) {
    for (const Warning& warning : run.warnings) {
      out << "- **" << run.model << "**: " << warning.id << ": " << warning.message << "\n";
    }
  }
  if (out.tellp() == 0) {
    return "";
  }
  return "Plausibility warnings (stable runs whose numbers are not a tissue's; thresholds in "
         "harness/run/plausibility.h):\n\n"
         + out.str() + "\n";
}

std::string summary_markdown(const scenes::Scene& scene, const std::vector<ModelRun>& runs) {
  std::ostringstream out;
  out << "# " << scene.name << "\n\n";
  if (!scene.description.empty()) {
    out << scene.description << "\n\n";
  }
  out << "dt = " << scene.dt << " s, " << scene.num_steps() << " steps; steps/s is the steps "
      << "after warm-up over their summed time (a mean rate), around step() alone and around "
      << "step() with the step's collision work; step ms are percentiles over the same steps, "
      << "around step() alone.\n\n";
  out << "| model | stable | steps/s | steps/s with collision | step ms (median / p95 / max) | "
         "iterations | max inverted tets | max volume change | recovery residual | "
         "time to 1% (s) | max penetration (mm) | peak tool force (N) | warnings |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ModelRun& run : runs) {
    out << "| " << run.model << " | "
        << (run.stability.stable ? "yes"
                                 : "NO (step " + std::to_string(*run.stability.diverged_at_step)
                                       + ": " + run.stability.divergence + ")")
        << (run.timing.interrupted ? " (interrupted after step "
                                         + std::to_string(run.timing.steps_run) + " of "
                                         + std::to_string(run.timing.steps_planned) + ")"
                                   : "")
        << " | " << fixed(run.timing.steps_per_second, 0) << " | "
        << fixed(run.timing.steps_per_second_with_collision, 0) << " | "
        << fixed(run.timing.step_ms.median, 3) << " / " << fixed(run.timing.step_ms.p95, 3) << " / "
        << fixed(run.timing.step_ms.max, 3) << " | " << fixed(run.solver.mean_iterations, 1)
        << " | " << run.shape.max_inverted_tets << " | "
        << fixed(100.0 * run.shape.volume_change, 2) << "% | "
        << (run.recovery.measured ? fixed(100.0 * run.recovery.residual, 2) + "%" : "-") << " | "
        << (run.recovery.time_to_one_percent ? fixed(*run.recovery.time_to_one_percent, 2) : "-")
        << " | " << fixed(1000.0 * run.contact.max_penetration, 2) << " | "
        << fixed(run.contact.peak_tool_force, 3) << " | " << warnings_cell(run) << " |\n";
  }
  const std::string warnings = warnings_markdown(runs);
  if (!warnings.empty()) {
    out << "\n" << warnings;
  }
  return out.str();
}

void write_reports(const std::filesystem::path& out_dir,
                   const scenes::Scene& scene,
                   const std::vector<ModelRun>& runs) {
  write_report_files(out_dir, {{"metrics.json", metrics_json(scene, runs).dump(2) + "\n"},
                               {"summary.md", summary_markdown(scene, runs)}});
}

}  // namespace softbench::harness
