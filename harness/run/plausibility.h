// SPDX-License-Identifier: MIT
// Plausibility: whether a run that stayed within the scene's limits (stable, RunMonitor's rule)
// also produced physically meaningful numbers. A stable run can still report a 900% volume change
// for a nearly incompressible tissue, a tool pressing 2 cm into the liver and reading 2e-6 N, or
// force on a tool that has been withdrawn. Those are not divergences (the run goes on and its
// numbers are reported), but every report shows them beside the stability verdict as warnings.
// The thresholds live here, in PlausibilityLimits, and nowhere else.
#pragma once

#include "harness/run/runner.h"
#include "scenes/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace softbench::harness {

/// The thresholds of the plausibility checks, each with the reason for its default.
struct PlausibilityLimits {
  /// Largest |V(t) - V0| / V0 over the run. Soft tissue is nearly incompressible (Poisson's
  /// ratio 0.45-0.49; liver is mostly water): under a probe and gravity its volume changes by a
  /// few percent at most. On the liver scenes the corotational FEM stays near 7% with the
  /// thesis's nu = 0.3; 20% leaves room for compressible test materials and still catches the
  /// hundreds of percent of linear FEM under rotation or an unconverged shape matching.
  double max_volume_change = 0.2;
  /// Largest fraction of the tets inverted at once. Tissue cannot turn inside out; a handful of
  /// slivers next to a point load inverting for a step is a discretisation artefact (5 of the
  /// liver's 4777 tets for the corotational FEM under the probe), a percent of the mesh is a fold
  /// a viewer sees.
  double max_inverted_fraction = 0.01;
  /// Tets still inverted at the end of the run: more than this is a body stuck inverted (tissue
  /// has no inverted state to come to rest in; the model did not bring them back).
  int max_final_inverted_tets = 0;
  /// A withdrawn tool (after the scene's release and after the tool's path has ended, or after
  /// a scene grasp's release) carries no load: a force above both of these is left over from a
  /// constraint that did not let go. Absolute: about the weight of a gram, far below what the
  /// probe reads while it presses the liver (0.4-20 N); relative: 1% of the run's peak, so that
  /// round-off on a stiff model's large forces is not flagged.
  double withdrawn_force = 0.01;          ///< N
  double withdrawn_force_of_peak = 0.01;  ///< fraction of ContactMetrics::peak_tool_force
  /// A tool that went this far into the tissue (ContactMetrics::loaded_travel) ...
  double min_loaded_travel = 1e-3;  ///< m
  /// ... must read at least this force. A 5 mm probe pressing 1 mm into the softest tissue here
  /// (E = 3 kPa) reads about 0.015 N (flat punch: 2 E a d / (1 - nu^2)); 1 mN is a fifteenth of
  /// that, and a model whose reported force stays below it does not report its contact force.
  double min_loaded_force = 1e-3;  ///< N
  /// The contact keeps the tissue the instrument's contact_margin away from the tool; a tissue
  /// vertex deeper inside the tool than the margin plus this, while the tool presses, is contact
  /// that did not hold (ContactMetrics::max_penetration_pressing).
  double penetration_slack = 1e-4;  ///< m
  /// Linear solves that stopped at their iteration cap (SolverMetrics::truncated_solves): a
  /// truncated solve's step has less than the accuracy its tolerance asks, and its error
  /// carries into every later step; none is the only count a default solver should show.
  int max_truncated_solves = 0;
  /// Steps whose contact holds were still changing when their passes ran out
  /// (ContactMetrics::unsettled_steps): each kept a pass the contact would have corrected, so
  /// its force and penetration are not a settled contact's.
  int max_unsettled_contact_steps = 0;
};

// The ids of Warning (runner.h).
inline constexpr const char* kWarningVolumeChange = "volume_change";
inline constexpr const char* kWarningInvertedTets = "inverted_tets";
inline constexpr const char* kWarningStuckInverted = "stuck_inverted";
inline constexpr const char* kWarningForceAfterWithdrawal = "force_after_withdrawal";
inline constexpr const char* kWarningNoContactForce = "no_contact_force";
inline constexpr const char* kWarningPenetration = "penetration";
inline constexpr const char* kWarningTruncatedSolves = "truncated_solves";
inline constexpr const char* kWarningUnsettledContact = "unsettled_contact";

/// s: from when the scene's tool carries no load: a scene grasp's release; an instrument's
/// release or the end of its path, whichever is later (it is still withdrawing before). Never
/// (scenes::kNever) without a tool or a release.
double tool_withdrawn_time(const scenes::Scene& scene);

/// The warning for tets still inverted at the end of a run, if any: shared with the stability
/// report, whose runs know only their inverted-tet counts.
std::optional<Warning> stuck_inverted_warning(int final_inverted_tets,
                                              const PlausibilityLimits& limits = {});

/// Judges a finished run of `scene`: volume change, inverted tets (at once and at the end), force
/// on a withdrawn tool (ModelRun::samples), a tool that went into the tissue but read no force,
/// penetration deeper than the instrument's margin while it pressed. A run that diverged gets
/// none: its numbers are already reported as meaningless, and its warnings would only repeat it.
std::vector<Warning> judge_plausibility(const ModelRun& run,
                                        const scenes::Scene& scene,
                                        const PlausibilityLimits& limits = {});

}  // namespace softbench::harness
