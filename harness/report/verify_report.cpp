// SPDX-License-Identifier: MIT
#include "harness/report/verify_report.h"

#include "harness/report/report_files.h"
#include "harness/format.h"
#include "harness/provenance.h"
#include "harness/verify/verify_tolerances.h"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

nlohmann::json material_json(const Material& material) {
  return {{"young_modulus_pa", material.young_modulus},
          {"poisson_ratio", material.poisson_ratio},
          {"density", material.density}};
}

nlohmann::json settings_json(const VerifySettings& settings) {
  return {{"quick", settings.quick},
          // Every case runs on one OpenMP thread (case_support.h: OneThread), whatever the
          // provenance's thread count says about the process.
          {"threads", 1},
          {"dt_s", settings.dt},
          {"material", material_json(settings.material)},
          {"max_wall_seconds", settings.max_wall_seconds},
          {"settle_speed_diagonals_per_s", settings.settle_speed},
          {"settle_steps", settings.settle_steps},
          {"max_settle_steps", settings.max_settle_steps},
          {"patch", {{"size_m", settings.patch_size},
                     {"cells", settings.patch_cells},
                     {"strain", settings.patch_strain}}},
          {"rigid_motion", {{"steps", settings.rigid_steps}}},
          {"cantilever", {{"length_m", settings.beam_length},
                          {"side_m", settings.beam_side},
                          {"material", material_json(settings.beam_material)},
                          {"cells_across", settings.beam_levels}}},
          {"hertz", {{"sphere_radius_m", settings.sphere_radius},
                     {"sphere_levels", settings.sphere_levels},
                     {"material", material_json(settings.hertz_material)},
                     {"depths_over_radius", settings.depths},
                     {"block_side_contact_radii", settings.block_side},
                     {"block_depth_contact_radii", settings.block_depth},
                     {"fine_spacing_contact_radii", settings.fine_spacing},
                     {"fine_extent_contact_radii", settings.fine_extent},
                     {"growth", settings.growth},
                     {"ramp_s", settings.ramp_seconds},
                     {"hold_s", settings.hold_seconds}}},
          {"free_spin", {{"rate_rad_s", settings.spin.rate},
                         {"axis", {settings.spin.axis.x(), settings.spin.axis.y(),
                                   settings.spin.axis.z()}},
                         {"duration_s", settings.spin.duration},
                         {"dt_s", settings.spin.dt}}},
          {"squash_release", {{"recovery_window_s", settings.recovery_window}}}};
}

nlohmann::json measure_json(const Measure& measure) {
  return {{"name", measure.name},
          {"value", number_or_null(measure.value)},
          {"target", measure.target},
          {"tolerance", measure.tolerance ? nlohmann::json(*measure.tolerance)
                                          : nlohmann::json(nullptr)},
          {"judged", measure.judged()},
          {"pass", measure.judged() ? nlohmann::json(measure.passes()) : nlohmann::json(nullptr)},
          {"unit", measure.unit}};
}

nlohmann::json case_json(const CaseResult& result) {
  nlohmann::json measures = nlohmann::json::array();
  for (const Measure& measure : result.measures) {
    measures.push_back(measure_json(measure));
  }
  return {{"name", result.name},
          {"status", to_string(result.status)},
          {"note", result.note},
          {"seconds", result.seconds},
          {"measures", measures},
          {"details", result.details}};
}

/// A value for the table: 3 significant digits, scientific where small.
std::string cell_value(double value) {
  if (!std::isfinite(value)) {
    return "-";
  }
  std::ostringstream out;
  const double magnitude = std::abs(value);
  if (magnitude != 0.0 && (magnitude < 1e-3 || magnitude >= 1e4)) {
    out << std::scientific << std::setprecision(1) << value;
  } else {
    out << std::setprecision(3) << value;
  }
  return out.str();
}

std::string badge(CaseStatus status) {
  switch (status) {
    case CaseStatus::kPass:
      return "**PASS**";
    case CaseStatus::kFail:
      return "**FAIL**";
    case CaseStatus::kNotApplicable:
      return "n/a";
  }
  return "?";
}

/// What a measure must be: "<= tol" for an error (target 0), "target +- tol" for a ratio.
std::string bound(double target, double tolerance) {
  return target == 0.0 ? "<= " + cell_value(tolerance)
                       : cell_value(target) + " +- " + cell_value(tolerance);
}

/// The headline of each case: what the table shows and what it must be (from the one table of
/// tolerances).
struct Column {
  std::string name;
  std::string headline;
  std::string tolerance;
};

std::vector<Column> columns() {
  namespace tol = verify_tolerance;
  return {
      {"patch", "interior error / imposed displacement", bound(0.0, tol::kPatch)},
      {"rigid_motion", "max displacement / diagonal (and elastic energy / E V)",
       bound(0.0, tol::kRigidDisplacement) + " (" + bound(0.0, tol::kRigidEnergy) + ")"},
      {"cantilever",
       "relative error of the tip deflection against Euler-Bernoulli's at the finest level "
       "(and, for a model whose stiffness is E, the error falls with refinement)",
       bound(0.0, tol::kCantilever)},
      {"hertz", "force / Hertz's at the deepest point", bound(1.0, tol::kHertz)},
      {"free_spin", "angular momentum drift (and shape error / diagonal)",
       bound(0.0, tol::kSpinMomentum) + " (" + bound(0.0, tol::kSpinShape) + ")"},
      {"squash_release", "recovery residual / diagonal", bound(0.0, tol::kSquashResidual)},
  };
}

}  // namespace

nlohmann::json verify_json(const VerifyReport& report) {
  nlohmann::json json;
  json["schema_version"] = kVerifySchemaVersion;
  json["provenance"] = to_json(provenance());
  json["settings"] = settings_json(report.settings);
  json["tolerances"] = {{"patch", verify_tolerance::kPatch},
                        {"rigid_motion_displacement", verify_tolerance::kRigidDisplacement},
                        {"rigid_motion_energy", verify_tolerance::kRigidEnergy},
                        {"cantilever", verify_tolerance::kCantilever},
                        {"hertz", verify_tolerance::kHertz},
                        {"free_spin_momentum", verify_tolerance::kSpinMomentum},
                        {"free_spin_shape", verify_tolerance::kSpinShape},
                        {"squash_release", verify_tolerance::kSquashResidual}};
  nlohmann::json models = nlohmann::json::array();
  for (const ModelVerification& model : report.models) {
    nlohmann::json cases = nlohmann::json::array();
    int passed = 0;
    int failed = 0;
    for (const CaseResult& result : model.cases) {
      cases.push_back(case_json(result));
      passed += result.status == CaseStatus::kPass ? 1 : 0;
      failed += result.status == CaseStatus::kFail ? 1 : 0;
    }
    models.push_back({{"model", model.model},
                      {"passed", passed},
                      {"failed", failed},
                      {"seconds", model.seconds},
                      {"cases", cases}});
  }
  json["models"] = models;
  json["wall_seconds"] = report.wall_seconds;
  return json;
}

std::string verify_markdown(const VerifyReport& report) {
  std::ostringstream out;
  out << "# softbench verify" << (report.settings.quick ? " (--quick)" : "") << "\n\n"
      << "Analytic verification cases, each model with its defaults (see `softbench verify "
         "--help` and docs/architecture.md). A cell: the case's headline value and its verdict, "
         "its wall time in brackets.\n\n";
  std::vector<std::string> names;
  if (!report.models.empty()) {
    for (const CaseResult& result : report.models.front().cases) {
      names.push_back(result.name);
    }
  }
  out << "| model |";
  for (const std::string& name : names) {
    out << " " << name << " |";
  }
  out << "\n|---|";
  for (std::size_t i = 0; i < names.size(); ++i) {
    out << "---|";
  }
  out << "\n";
  for (const ModelVerification& model : report.models) {
    out << "| " << model.model << " |";
    for (const CaseResult& result : model.cases) {
      const double value = result.measures.empty() ? std::nan("") : result.measures.front().value;
      out << " " << cell_value(value) << " " << badge(result.status) << " ("
          << fixed(result.seconds, 2) << " s) |";
    }
    out << "\n";
  }
  out << "\n## What each column measures\n\n| case | value | tolerance |\n|---|---|---|\n";
  for (const Column& column : columns()) {
    out << "| " << column.name << " | " << column.headline << " | " << column.tolerance
        << " |\n";
  }
  out << "\nThe reasons for each tolerance: `harness/verify/verify_tolerances.h`.\n";

  out << "\n## Details\n\n";
  for (const ModelVerification& model : report.models) {
    out << "### " << model.model << " (" << fixed(model.seconds, 1) << " s)\n\n";
    for (const CaseResult& result : model.cases) {
      out << "- " << result.name << ": " << badge(result.status);
      for (const Measure& measure : result.measures) {
        out << "; " << measure.name << " " << cell_value(measure.value);
        if (measure.tolerance) {
          out << " (" << (measure.passes() ? "within" : "outside") << " "
              << bound(measure.target, *measure.tolerance) << ")";
        }
      }
      if (!result.note.empty()) {
        out << ". " << result.note;
      }
      out << "\n";
    }
    out << "\n";
  }
  out << "Total: " << fixed(report.wall_seconds, 1) << " s.\n";
  return out.str();
}

void write_verify(const std::filesystem::path& out_dir, const VerifyReport& report) {
  write_report_files(out_dir, {{"verify.json", verify_json(report).dump(2) + "\n"},
                               {"verify.md", verify_markdown(report)}});
}

}  // namespace softbench::harness
