// SPDX-License-Identifier: MIT
#pragma once

#include "harness/verify/free_spin.h"
#include "models/material.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace softbench::harness {

// `softbench verify`: analytic verification cases run on every registered model, each on a mesh
// made in code (nothing is read from a file), each judged against a tolerance stated once in
// verify_tolerances.h:
//
// - patch: a block under an affine (uniform-strain) boundary displacement, the interior free,
//   settled: the interior's distance from the affine field, relative to the imposed displacement.
// - rigid_motion: the rest shape rotated 90 degrees about an oblique axis and translated, free,
//   no gravity: how far it moves from there (and the elastic energy it stores).
// - cantilever: a clamped beam under its own weight at 2-3 mesh levels against Euler-Bernoulli's
//   tip deflection w L^4 / (8 E I).
// - hertz: a rigid sphere pressed into a block fixed at its base, through the run command's
//   instrument contact: the tool's force against Hertz's 4/3 E/(1 - nu^2) sqrt(R) d^(3/2).
// - free_spin: a box spinning about an oblique axis, undamped, 2 s: angular momentum drift and
//   shape error (free_spin.h).
// - squash_release: the stability command's squash torture and recovery (run_torture).
//
// Each model runs with its defaults, plus for the cases that compare with a material law the
// parameters its registry entry names for a stiffness that follows the material
// (ModelInfo::stiffness_axis.fixed_params, e.g. mass_spring's springs from E), and for the
// static cases its settling damping (ModelInfo::settling_damping), which changes the
// equilibrium of none of them. A model whose stiffness is not a material constant (shape
// matching, bullet_softbody) cannot match an analytic elastic solution: it runs the cases all
// the same and its numbers are reported, with a note.

enum class CaseStatus {
  kPass,
  kFail,           ///< measured out of tolerance, or the run blew up or ran out of time
  kNotApplicable,  ///< the case cannot be judged for this model (the reason says why)
};
/// "pass", "fail", "n/a".
std::string to_string(CaseStatus status);

/// One measured quantity of a case. A judged measure passes when |value - target| <= tolerance.
struct Measure {
  std::string name;  ///< stable key, e.g. "interior_error"
  double value = 0.0;  ///< NaN when it could not be measured
  double target = 0.0;
  std::optional<double> tolerance;  ///< empty: reported, not judged
  std::string unit;                 ///< what value is, e.g. "of the imposed displacement"

  bool judged() const { return tolerance.has_value(); }
  bool passes() const;
};

struct CaseResult {
  std::string name;  ///< "patch", "rigid_motion", ...
  /// kPass until judged (judge() in case_support.h): a blow-up sets kFail first, a case that
  /// does not apply kNotApplicable, and the judged measures decide the rest.
  CaseStatus status = CaseStatus::kPass;
  /// Why it failed or does not apply, or what to know about the numbers ("" when nothing).
  std::string note;
  std::vector<Measure> measures;  ///< the first is the headline value of the tables
  double seconds = 0.0;           ///< wall time of the case
  /// Per-case detail for verify.json (mesh levels, depths, steps).
  nlohmann::json details = nlohmann::json::object();
};

/// Everything the cases are made of. default_verify_settings() and quick_verify_settings() give
/// the two sets the command runs; tests change single fields.
struct VerifySettings {
  bool quick = false;
  double dt = 1.0 / 60.0;  ///< s, the scenes' step, for every case
  /// The scenes' liver material: patch, rigid motion, free spin, squash.
  Material material{3000.0, 0.3, 1060.0};
  /// s of wall time per simulation (a cantilever level, the press); beyond it the case fails as
  /// timed out, so no model can hang the command.
  double max_wall_seconds = 60.0;
  /// A static case has settled once every free vertex has been slower than this many bbox
  /// diagonals per second for `settle_steps` steps in a row: the displacement left to come is
  /// then ~speed / lowest frequency, 1e-8 of the diagonal on these bodies, far below every
  /// tolerance.
  double settle_speed = 1e-6;
  int settle_steps = 10;
  int max_settle_steps = 1200;  ///< 20 s at the scenes' step

  // patch: a cube of `patch_size` in patch_cells^3 cells, displaced on its boundary by
  // u = G (X - centre), G with entries up to patch_strain (stretch, shear and rotation).
  double patch_size = 0.05;  ///< m
  int patch_cells = 4;
  double patch_strain = 0.02;

  // rigid_motion: the spin box rotated and translated, then rigid_steps free steps.
  int rigid_steps = 60;

  // cantilever: a square beam clamped at x = 0, under its own weight. Stiff enough that the tip
  // deflects ~1.6% of the length (Euler-Bernoulli's small-deflection range).
  double beam_length = 0.10;  ///< m
  double beam_side = 0.01;    ///< m
  Material beam_material{1e7, 0.3, 1060.0};
  std::vector<int> beam_levels{1, 2, 4};  ///< cells across the side (10x as many along)
  /// The E the analytic deflection is computed with; empty: the beam's. Only for checking that
  /// the case can fail (a wrong E must fail it).
  std::optional<double> analytic_young_modulus;

  // hertz: a sphere of `sphere_radius` pressed to `depths` (x the radius) into a block of
  // block_side x block_side x block_depth contact radii (sqrt(R d) at the deepest), fixed at its
  // base, meshed on a graded grid: `fine_spacing` contact radii under the sphere (out to
  // `fine_extent` contact radii from the axis and from the top), growing by `growth` per cell
  // beyond.
  double sphere_radius = 0.01;  ///< m
  int sphere_levels = 4;        ///< icosphere subdivisions (5120 triangles)
  Material hertz_material{10000.0, 0.3, 1000.0};
  std::vector<double> depths{0.1, 0.2, 0.3};
  double block_side = 10.0;
  double block_depth = 5.0;
  double fine_spacing = 0.15;
  double fine_extent = 1.2;
  double growth = 1.4;
  double ramp_seconds = 0.25;  ///< s to go from one depth to the next
  double hold_seconds = 0.25;  ///< s held at each depth before the force is read

  // free_spin: the spin box (10 x 6 x 4 cm in 2 cm cells), free_spin.h's motion.
  SpinMotion spin;

  // squash_release: the spin box, its x = 0 face held, squashed flat and let go.
  double recovery_window = 10.0;  ///< s
};

/// The full cases: three cantilever levels, the Hertz block on a 24k-tet graded mesh.
VerifySettings default_verify_settings();
/// Coarse variants for CI: two cantilever levels (the full run's finer two), a coarser Hertz
/// block, shorter runs.
VerifySettings quick_verify_settings();

/// What the cases run: a registered model and the parameters merged over its defaults (the
/// command passes none; tests pass e.g. a deliberately wrong formulation).
struct ModelUnderTest {
  std::string name;
  nlohmann::json params = nlohmann::json::object();
};

CaseResult patch_case(const ModelUnderTest& model, const VerifySettings& settings);
CaseResult rigid_motion_case(const ModelUnderTest& model, const VerifySettings& settings);
CaseResult cantilever_case(const ModelUnderTest& model, const VerifySettings& settings);
CaseResult hertz_case(const ModelUnderTest& model, const VerifySettings& settings);
CaseResult free_spin_case(const ModelUnderTest& model, const VerifySettings& settings);
CaseResult squash_release_case(const ModelUnderTest& model, const VerifySettings& settings);

/// The case names, in table order.
const std::vector<std::string>& verify_case_names();
/// Runs the named case (one of verify_case_names()).
CaseResult run_case(const std::string& name,
                    const ModelUnderTest& model,
                    const VerifySettings& settings);

struct ModelVerification {
  std::string model;
  std::vector<CaseResult> cases;  ///< in verify_case_names() order
  double seconds = 0.0;
};

struct VerifyOptions {
  std::vector<std::string> models;  ///< empty: the registry's default names
  VerifySettings settings = default_verify_settings();
  std::vector<std::string> cases;   ///< empty: every case
  std::ostream* progress = nullptr;  ///< a line per case
};

struct VerifyReport {
  VerifySettings settings;
  std::vector<ModelVerification> models;
  double wall_seconds = 0.0;
};

/// Runs every case on every model. Throws InputError for an unknown model or case name before
/// anything runs; a model that blows up or misses a tolerance is a result.
VerifyReport run_verify(const VerifyOptions& options);

}  // namespace softbench::harness
