// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "harness/claim.h"
#include "harness/stability/stability_run.h"
#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace softbench::harness {

// `softbench stability SCENE`: where each model stays stable, and what it survives. Two parts
// per model:
//
// - The stability map: for each stiffness on the model's axis, the largest stable time step.
//   Time steps are tried from the largest down, halving, and the scan stops at the first stable
//   one (larger steps are the harder ones for every integrator here; smaller steps than the
//   first stable one are not run). A run is `map_duration` of the scene's fixed region and
//   gravity, from rest (the scene's initial velocity is not used).
// - The torture cases: the body forced into an extreme shape and let go (squash, collapse,
//   scramble, stretch: run_torture), or the scene's own loading with an extreme material or mesh
//   (near-incompressible, sliver: run_scene_loading), each judged stable / recovered / NaN.

/// What a model's stiffness axis varies, and how.
struct StiffnessAxis {
  std::string parameter;  ///< "young_modulus", or the model parameter's key ("alpha", ...)
  std::string unit;       ///< "Pa", or "" for a parameter without a unit
  bool material = true;   ///< true: the material's Young's modulus; false: params[parameter]
  /// Extra parameters set for every map run (mass_spring: springs derived from E).
  nlohmann::json fixed_params = nlohmann::json::object();
  std::vector<double> values;  ///< increasing
  std::string note;            ///< one line for the report
};

/// The axis `model` is mapped along, as its registry entry declares it (ModelInfo::
/// stiffness_axis): `young_moduli` for a model whose stiffness follows the material, `unitless`
/// values of its parameter for one whose stiffness is not a material constant.
StiffnessAxis stiffness_axis(const std::string& model,
                             const std::vector<double>& young_moduli,
                             const std::vector<double>& unitless);

enum class TortureCase {
  kSquash,          ///< every vertex onto a plane through the centroid
  kCollapse,        ///< every vertex into a tiny ball around the centroid
  kScramble,        ///< every vertex to a random point of the bounding box
  kStretch,         ///< 3x along the longest axis
  kIncompressible,  ///< the scene's loading with Poisson's ratio 0.49
  kSliver,          ///< the scene's loading on the mesh with one tet flattened
};
inline constexpr TortureCase kAllTortureCases[] = {
    TortureCase::kSquash,  TortureCase::kCollapse,       TortureCase::kScramble,
    TortureCase::kStretch, TortureCase::kIncompressible, TortureCase::kSliver};
/// "squash_to_plane", "collapse_to_point", "scramble", "stretch_3x", "poisson_0.49", "sliver_tet".
std::string torture_name(TortureCase which);
/// The shape tortures: the large deformations of the thesis's claim about mass-spring.
bool is_large_deformation(TortureCase which);

struct StabilitySettings {
  std::vector<double> young_moduli;  ///< Pa, the map's axis for material models
  std::vector<double> unitless;      ///< alpha (shape_matching) and kLST (bullet_softbody)
  std::vector<double> time_steps;    ///< s, decreasing: tried in this order
  double map_duration = 1.0;         ///< s of simulated time per map run
  std::vector<TortureCase> cases{std::begin(kAllTortureCases), std::end(kAllTortureCases)};
  /// s of recovery after a torture (or the scene's release). Shape matching recovers slowly (its
  /// pull is per step and the liver hangs from 7% of its vertices): ~10-20 s on the liver.
  double recovery_window = 10.0;
  double stretch_factor = 3.0;
  double collapse_radius = 1e-3;  ///< x the bbox diagonal
  double incompressible_poisson = 0.49;
  double sliver_quality = 1e-3;   ///< the flattened tet's radius ratio
  std::uint64_t seed = 9;         ///< scramble and collapse
  int max_steps_per_run = 20000;  ///< steps beyond it are not planned (map_duration capped)
  /// s; a run over it is reported as timed out. The reference (neo_hookean) and
  /// bullet_deformable take ~0.3-1 s per step on the liver and hit it.
  /// The full grid on the liver took 15.6 min with 60 s (of which neo_hookean 9.8 min and
  /// bullet_deformable 4.9 min); 30 s keeps it near 10 min.
  double max_wall_seconds_per_run = 30.0;
};

/// E = 1e2 .. 1e6 Pa (5), alpha/kLST = 0.01 .. 1 (5), dt = 1/30 .. 1/3840 s (8, halving), 1 s
/// map runs, 10 s recovery window, 30 s wall budget per run.
StabilitySettings default_stability_settings();
/// A small grid for tests and CI: E = 1e3, 1e5 Pa; alpha/kLST = 0.1, 1; dt = 1/30 .. 1/120 s;
/// 0.25 s map runs; 2 s recovery window; 10 s wall budget per run.
StabilitySettings quick_stability_settings();

/// "1/60" for a time step 1/n s, else the number (no unit).
std::string time_step_label(double dt);

struct MapCell {
  double dt = 0.0;                    ///< s
  std::optional<RunVerdict> verdict;  ///< empty: not run (a larger dt was stable, or timed out)
  bool is(RunStatus status) const { return verdict && verdict->status == status; }
};

/// One stiffness of the map: a cell per time step.
struct MapRow {
  double value = 0.0;  ///< on the model's axis
  std::vector<MapCell> cells;
  std::optional<double> max_stable_dt;  ///< s; empty when no time step was stable
};

/// Runs `run(dt)` for each of `time_steps` (decreasing) until one is stable; the rest get a
/// cell with an empty verdict (not run). A run that times out also ends the scan (a smaller
/// step would take longer still): the row then has no max_stable_dt, and its last cell says
/// kTimedOut.
MapRow scan_time_steps(double value,
                       const std::vector<double>& time_steps,
                       const std::function<RunVerdict(double dt)>& run);

struct TortureResult {
  TortureCase which = TortureCase::kSquash;
  bool run = false;  ///< false when the case could not be set up (see note)
  std::string note;  ///< how it was set up (e.g. which tet was flattened)
  RunVerdict verdict;
  bool recovered = false;  ///< verdict.recovered()
};

struct ModelStability {
  std::string model;
  nlohmann::json params;  ///< the scene's block, as the torture cases use it
  StiffnessAxis axis;
  std::vector<MapRow> map;
  std::vector<TortureResult> torture;
  double wall_seconds = 0.0;
};

/// The map and torture cases of one model on `mesh` under `scene` (its fixed region, gravity,
/// limits, dt for the tortures, material, per-model parameters and loading). The scene's mesh
/// path is not read: `mesh` is the body (a test may pass a mesh made in code). Throws
/// InputError for an unknown model, a bad parameter block, or a scene whose fixed region selects
/// no vertex (a free body: the map and the torture cases hang the body from its fixed region).
ModelStability model_stability(const scenes::Scene& scene,
                               const SceneMesh& mesh,
                               const std::string& model,
                               const StabilitySettings& settings,
                               std::ostream* progress = nullptr);

/// "Shape matching is unconditionally stable" (pass: every map cell run and every torture case
/// stable) and "mass-spring may fail at large deformation" (observed: unstable or not recovered
/// in some shape torture; a possibility, so not observed is no failure).
std::vector<Claim> check_claims(const std::vector<ModelStability>& models,
                                const StabilitySettings& settings);

struct StabilityReport {
  std::string scene;
  std::string scene_file;
  int vertices = 0;
  int tets = 0;
  double scene_dt = 0.0;  ///< s, the torture cases' time step
  StabilitySettings settings;
  std::vector<ModelStability> models;
  std::vector<Claim> claims;
  double wall_seconds = 0.0;
};

struct StabilityOptions {
  std::vector<std::string> models;  ///< empty: every registered model
  StabilitySettings settings = default_stability_settings();
  std::ostream* progress = nullptr;  ///< a line per map row and torture case
};

/// Reads the scene's mesh and runs model_stability for each model.
StabilityReport run_stability(const scenes::Scene& scene, const StabilityOptions& options);

}  // namespace softbench::harness
