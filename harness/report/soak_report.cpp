// SPDX-License-Identifier: MIT
#include "harness/report/soak_report.h"

#include "harness/report/report_files.h"
#include "harness/format.h"
#include "harness/provenance.h"

#include <sstream>

namespace softbench::harness {
namespace {

double mebibytes(std::size_t bytes) {
  return static_cast<double>(bytes) / (1024.0 * 1024.0);
}

nlohmann::json cycle_json(const SoakCycle& cycle) {
  return {{"cycle", cycle.cycle},
          {"steps", cycle.steps},
          {"steps_per_second", cycle.steps_per_second},
          {"cpu_ms_per_step", cycle.cpu_ms_per_step},
          {"resident_bytes", cycle.resident_bytes},
          {"peak_resident_bytes", cycle.peak_resident_bytes},
          {"heap_bytes", cycle.heap_bytes},
          {"energy_j", number_or_null(cycle.energy)},
          {"kinetic_energy_j", number_or_null(cycle.kinetic_energy)},
          {"shape_drift", number_or_null(cycle.shape_drift)},
          {"peak_tool_force_n", number_or_null(cycle.peak_tool_force)},
          {"max_speed_m_per_s", number_or_null(cycle.max_speed)}};
}

}  // namespace

nlohmann::json soak_json(const SoakReport& report) {
  nlohmann::json json;
  json["schema_version"] = 1;
  json["provenance"] = to_json(provenance());
  json["scene"] = report.scene;
  json["model"] = report.model;
  json["mesh"] = {{"vertices", report.vertices}, {"tets", report.tets}};
  json["dt_s"] = report.dt;
  json["steps_per_cycle"] = report.steps_per_cycle;
  json["steps_planned"] = report.steps_planned;
  json["steps_run"] = report.steps_run;
  json["stable"] = report.stable;
  json["interrupted"] = report.interrupted;
  json["diverged_at_step"] =
      report.diverged_at_step ? nlohmann::json(*report.diverged_at_step) : nlohmann::json(nullptr);
  json["divergence"] = report.divergence;
  json["wall_seconds"] = report.wall_seconds;
  json["summary"] = {{"resident_after_warmup_bytes", report.resident_after_warmup},
                     {"resident_at_end_bytes", report.resident_at_end},
                     {"peak_resident_bytes", report.peak_resident},
                     {"heap_at_half_bytes", report.heap_at_half},
                     {"heap_at_end_bytes", report.heap_at_end},
                     {"heap_growth_bytes_per_step", report.heap_growth_per_step},
                     {"energy_drift", number_or_null(report.energy_drift)},
                     {"final_shape_drift", number_or_null(report.final_shape_drift)},
                     {"speed_ratio_late_over_early", number_or_null(report.speed_ratio)}};
  json["cycles"] = nlohmann::json::array();
  for (const SoakCycle& cycle : report.cycles) {
    json["cycles"].push_back(cycle_json(cycle));
  }
  return json;
}

std::string soak_markdown(const SoakReport& report) {
  std::ostringstream out;
  out << "# Soak: " << report.model << " on " << report.scene << "\n\n";
  out << report.steps_run << " of " << report.steps_planned << " steps ("
      << report.steps_per_cycle << " a cycle, dt " << report.dt << " s) on " << report.vertices
      << " vertices, " << report.tets << " tets, in " << fixed(report.wall_seconds, 1)
      << " s: "
      << (report.stable ? std::string("stable")
                        : "UNSTABLE at step " + std::to_string(*report.diverged_at_step) + " ("
                              + report.divergence + ")")
      << (report.interrupted ? "; interrupted (Ctrl-C or SIGTERM): the whole cycles before the "
                               "stop"
                             : "")
      << ".\n\n";
  out << "| measure | value |\n|---|---|\n";
  out << "| resident memory after warm-up (first tenth of the cycles) | "
      << fixed(mebibytes(report.resident_after_warmup), 1) << " MiB |\n";
  out << "| resident memory at the end | " << fixed(mebibytes(report.resident_at_end), 1)
      << " MiB (" << (report.resident_at_end >= report.resident_after_warmup ? "+" : "-")
      << fixed(mebibytes(report.resident_at_end >= report.resident_after_warmup
                             ? report.resident_at_end - report.resident_after_warmup
                             : report.resident_after_warmup - report.resident_at_end),
               1)
      << " MiB) |\n";
  out << "| peak resident memory | " << fixed(mebibytes(report.peak_resident), 1) << " MiB |\n";
  out << "| heap in use at the middle cycle's end / at the end | " << report.heap_at_half << " / "
      << report.heap_at_end << " bytes (" << fixed(report.heap_growth_per_step, 3)
      << " bytes a step between them) |\n";
  out << "| energy drift (last cycle's end against the first's) | "
      << fixed(100.0 * report.energy_drift, 3) << "% |\n";
  out << "| shape drift at the end (RMS / bbox diagonal, against the first cycle's end) | "
      << fixed(100.0 * report.final_shape_drift, 3) << "% |\n";
  out << "| speed, last tenth over first tenth (median steps/s) | "
      << fixed(report.speed_ratio, 3) << " |\n\n";
  out << "| cycle | steps | steps/s | CPU ms/step | RSS (MiB) | heap (bytes) | energy (J) | "
         "shape drift | peak tool force (N) |\n|---|---|---|---|---|---|---|---|---|\n";
  const std::size_t count = report.cycles.size();
  const std::size_t every = std::max<std::size_t>(1, count / 10);
  for (std::size_t i = 0; i < count; ++i) {
    if (i % every != 0 && i + 1 != count) {
      continue;
    }
    const SoakCycle& cycle = report.cycles[i];
    out << "| " << cycle.cycle << " | " << cycle.steps << " | " << fixed(cycle.steps_per_second, 0)
        << " | " << fixed(cycle.cpu_ms_per_step, 3) << " | "
        << fixed(mebibytes(cycle.resident_bytes), 1) << " | " << cycle.heap_bytes << " | "
        << cycle.energy << " | "
        << fixed(100.0 * cycle.shape_drift, 3) << "% | " << fixed(cycle.peak_tool_force, 3)
        << " |\n";
  }
  return out.str();
}

void write_soak(const std::filesystem::path& out_dir, const SoakReport& report) {
  write_report_files(out_dir, {{"soak.json", soak_json(report).dump(2) + "\n"},
                               {"soak.md", soak_markdown(report)}});
}

}  // namespace softbench::harness
