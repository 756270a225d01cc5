// SPDX-License-Identifier: MIT
#include "harness/run/plausibility.h"

#include "harness/format.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace softbench::harness {
namespace {

// Three significant digits: forces span 1e-6 to 100 N.
std::string g3(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

std::string millimetres(double metres) {
  return g3(1000.0 * metres) + " mm";
}

void judge_shape(const ModelRun& run, const PlausibilityLimits& limits, std::vector<Warning>& out) {
  const ShapeMetrics& shape = run.shape;
  if (!(shape.volume_change <= limits.max_volume_change)) {
    out.push_back({kWarningVolumeChange,
                   "the volume changed by up to " + percent(shape.volume_change)
                       + " (tissue is nearly incompressible: more than "
                       + percent(limits.max_volume_change) + " is not a tissue's deformation)"});
  }
  const double allowed = limits.max_inverted_fraction * std::max(run.tets, 0);
  if (static_cast<double>(shape.max_inverted_tets) > allowed) {
    std::string share;
    if (run.tets > 0) {
      share = " (" + percent(static_cast<double>(shape.max_inverted_tets) / run.tets) + " of "
              + std::to_string(run.tets) + ")";
    }
    out.push_back(
        {kWarningInvertedTets, "up to " + std::to_string(shape.max_inverted_tets)
                                   + " tets were inverted at once" + share + ", more than "
                                   + percent(limits.max_inverted_fraction) + " of the mesh"});
  }
  if (std::optional<Warning> stuck = stuck_inverted_warning(shape.final_inverted_tets, limits)) {
    out.push_back(*stuck);
  }
}

void judge_withdrawn_force(const ModelRun& run,
                           const scenes::Scene& scene,
                           const PlausibilityLimits& limits,
                           std::vector<Warning>& out) {
  const double withdrawn = tool_withdrawn_time(scene);
  if (!std::isfinite(withdrawn)) {
    return;
  }
  const double threshold = std::max(limits.withdrawn_force,
                                    limits.withdrawn_force_of_peak * run.contact.peak_tool_force);
  // The step after the withdrawal with the largest force: where it is worst.
  const StepSample* worst = nullptr;
  for (const StepSample& sample : run.samples) {
    if (sample.time > withdrawn + 0.5 * scene.dt && sample.tool_force > threshold
        && (worst == nullptr || sample.tool_force > worst->tool_force)) {
      worst = &sample;
    }
  }
  if (worst != nullptr) {
    out.push_back({kWarningForceAfterWithdrawal,
                   "the tool read " + g3(worst->tool_force) + " N at " + g3(worst->time)
                       + " s, after it was withdrawn at " + g3(withdrawn)
                       + " s (a withdrawn tool carries no load; above " + g3(limits.withdrawn_force)
                       + " N and " + percent(limits.withdrawn_force_of_peak) + " of its peak "
                       + g3(run.contact.peak_tool_force) + " N)"});
  }
}

void judge_contact(const ModelRun& run,
                   const scenes::Scene& scene,
                   const PlausibilityLimits& limits,
                   std::vector<Warning>& out) {
  const ContactMetrics& contact = run.contact;
  if (contact.loaded_travel >= limits.min_loaded_travel
      && contact.peak_tool_force < limits.min_loaded_force) {
    out.push_back({kWarningNoContactForce,
                   "the tool went " + millimetres(contact.loaded_travel)
                       + " into the tissue but read at most " + g3(contact.peak_tool_force)
                       + " N (below " + g3(limits.min_loaded_force)
                       + " N: the model does not report the force its contact takes)"});
  }
  if (!scene.instrument) {
    return;
  }
  if (contact.unsettled_steps > limits.max_unsettled_contact_steps) {
    out.push_back({kWarningUnsettledContact,
                   std::to_string(contact.unsettled_steps) + " of "
                       + std::to_string(run.timing.steps_run) + " steps ran out of contact passes ("
                       + std::to_string(scene.instrument->contact_passes)
                       + ") with the holds still changing: each kept a pass the contact would "
                         "have corrected, its force and penetration not a settled contact's"});
  }
  const double allowed = scene.instrument->contact_margin + limits.penetration_slack;
  if (contact.max_penetration_pressing > allowed) {
    out.push_back({kWarningPenetration,
                   "the tissue went " + millimetres(contact.max_penetration_pressing)
                       + " into the tool while it pressed (the contact keeps a "
                       + millimetres(scene.instrument->contact_margin) + " margin; above "
                       + millimetres(allowed) + " it did not hold)"});
  }
}

void judge_solver(const ModelRun& run,
                  const PlausibilityLimits& limits,
                  std::vector<Warning>& out) {
  const SolverMetrics& solver = run.solver;
  if (solver.truncated_solves > limits.max_truncated_solves) {
    out.push_back({kWarningTruncatedSolves,
                   std::to_string(solver.truncated_solves) + " of "
                       + std::to_string(solver.linear_solves)
                       + " linear solves stopped at their iteration cap before their tolerance: "
                         "those steps have less than the accuracy asked, and their error "
                         "carries on"});
  }
}

}  // namespace

double tool_withdrawn_time(const scenes::Scene& scene) {
  if (scene.grasp) {
    return scene.grasp->release;
  }
  if (scene.instrument && std::isfinite(scene.instrument->release)) {
    const double path_end =
        scene.instrument->path.empty() ? 0.0 : scene.instrument->path.back().time;
    return std::max(scene.instrument->release, path_end);
  }
  return scenes::kNever;
}

std::optional<Warning> stuck_inverted_warning(int final_inverted_tets,
                                              const PlausibilityLimits& limits) {
  if (final_inverted_tets <= limits.max_final_inverted_tets) {
    return std::nullopt;
  }
  return Warning{kWarningStuckInverted,
                 std::to_string(final_inverted_tets)
                     + " tets were still inverted at the end (stuck inverted: the model did not "
                       "bring them back)"};
}

std::vector<Warning> judge_plausibility(const ModelRun& run,
                                        const scenes::Scene& scene,
                                        const PlausibilityLimits& limits) {
  std::vector<Warning> warnings;
  if (!run.stability.stable) {
    return warnings;
  }
  judge_shape(run, limits, warnings);
  judge_withdrawn_force(run, scene, limits, warnings);
  judge_contact(run, scene, limits, warnings);
  judge_solver(run, limits, warnings);
  return warnings;
}

}  // namespace softbench::harness
