// SPDX-License-Identifier: MIT
// Sphere indentation against Hertz, through the machinery `softbench run` drives an instrument
// with: a scene built in memory (scenes::Scene, a SceneMesh made in code), SceneStepper (the
// fixed region, the instrument's path and its contact with the active set settled each step,
// the tool's force) and RunMonitor (the one divergence rule). run_scene would do the same steps
// but has no wall-clock budget, and a slow model on this mesh must not hang the command.
#include "geometry/mesh_validation.h"
#include "geometry/shape_meshes.h"
#include "harness/format.h"
#include "harness/run/run_monitor.h"
#include "harness/run/scene_mesh.h"
#include "harness/run/scene_stepper.h"
#include "harness/verify/case_support.h"
#include "harness/verify/verify.h"
#include "harness/verify/verify_tolerances.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace softbench::harness {

using namespace verify_detail;

namespace {


/// Coordinates from 0 to `extent`: `fine` spacing up to `fine_extent`, then cells growing by
/// `growth` each; the last cell is merged into the one before when it would be less than half
/// the size that one has.
std::vector<double> graded(double extent, double fine, double fine_extent, double growth) {
  std::vector<double> coordinates{0.0};
  double spacing = fine;
  while (coordinates.back() < extent) {
    const double next = coordinates.back() + spacing;
    if (next >= extent || extent - next < 0.5 * spacing * growth) {
      coordinates.push_back(extent);
      break;
    }
    coordinates.push_back(next);
    if (next >= fine_extent - 1e-12 * extent) {
      spacing *= growth;
    }
  }
  return coordinates;
}

}  // namespace

CaseResult hertz_case(const ModelUnderTest& model, const VerifySettings& settings) {
  CaseRun run("hertz");
  CaseResult& result = run.result;
  const Material& material = settings.hertz_material;

  // The contact keeps the tissue `margin` outside the tool: against a sphere of radius R that
  // is contact with a sphere of radius R + margin, and the depths are that sphere's.
  scenes::Instrument instrument;
  const double margin = instrument.contact_margin;
  const double radius = settings.sphere_radius + margin;
  const double deepest = settings.depths.back() * settings.sphere_radius;
  const double contact = std::sqrt(radius * deepest);  // Hertz's contact radius there

  // The block: top at z = 0, graded toward the contact. A quarter of it, x and y >= 0, on
  // frictionless supports in the planes x = 0 and y = 0 (the whole block's symmetry planes):
  // the same answer as the whole block for a quarter of its cost, so a finer mesh under the
  // sphere. The whole tool force is four times the quarter's along z (the quarters' sideways
  // forces cancel).
  const double fine = settings.fine_spacing * contact;
  const double fine_extent = settings.fine_extent * contact;
  const std::vector<double> across =
      graded(0.5 * settings.block_side * contact, fine, fine_extent, settings.growth);
  std::vector<double> down = graded(settings.block_depth * contact, fine, fine_extent,
                                    settings.growth);
  std::vector<double> zs;
  for (auto it = down.rbegin(); it != down.rend(); ++it) {
    zs.push_back(-*it);
  }
  const SceneMesh mesh{make_tet_mesh(grid_box_tets(across, across, zs)), "verify_hertz",
                       std::make_shared<TriMesh>(
                           icosphere(settings.sphere_levels, settings.sphere_radius))};

  scenes::Scene scene;
  scene.name = "verify_hertz";
  scene.source = "softbench verify (hertz)";
  scene.material = material;
  scene.gravity.acceleration.setZero();
  scene.dt = settings.dt;
  const double bottom = zs.front();
  const double hair = 1e-9 * settings.block_depth * contact;
  scene.fixed.box = scenes::Box{Eigen::Vector3d(-1e3, -1e3, bottom - hair),
                                Eigen::Vector3d(1e3, 1e3, bottom + hair)};
  scene.supports = {scenes::Plane{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), hair},
                    scenes::Plane{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), hair}};
  // The sphere's centre starts just out of contact and goes down a staircase: a ramp to each
  // depth, then a hold at it, after which the force is read (quasi-static).
  const auto centre_at = [&](double depth) { return Eigen::Vector3d(0.0, 0.0, radius - depth); };
  instrument.mesh = "icosphere";
  instrument.start = 0.0;
  instrument.path.push_back({0.0, centre_at(0.0), Eigen::Quaterniond::Identity()});
  std::vector<double> read_times;
  std::vector<double> hold_times;  ///< when each hold starts
  double time = 0.0;
  for (const double fraction : settings.depths) {
    time += settings.ramp_seconds;
    instrument.path.push_back({time, centre_at(fraction * settings.sphere_radius),
                               Eigen::Quaterniond::Identity()});
    hold_times.push_back(time);
    time += settings.hold_seconds;
    instrument.path.push_back({time, centre_at(fraction * settings.sphere_radius),
                               Eigen::Quaterniond::Identity()});
    read_times.push_back(time);
  }
  scene.instrument = instrument;
  scene.duration = time;

  const std::unique_ptr<SoftBody> body =
      build(model, mesh.body, material, static_params(model), result.name);
  SceneStepper stepper(scene, mesh);
  stepper.start(*body);
  RunMonitor monitor(mesh.body, scene.limits, mesh.diagonal());
  const double modulus = material.young_modulus / (1.0 - material.poisson_ratio
                                                             * material.poisson_ratio);
  std::vector<double> forces;
  // Over each hold, the force's two-step means from its second step on: the first step still
  // carries the ramp's damping force (the tissue was moving), and a vertex at the patch's rim
  // taken and let go on alternate steps makes a two-step ripple (about 1%) the mean removes.
  std::vector<double> hold_low(hold_times.size(), std::numeric_limits<double>::infinity());
  std::vector<double> hold_high(hold_times.size(), -std::numeric_limits<double>::infinity());
  std::size_t holds_begun = 0;
  int hold_steps = 0;  ///< steps into the current hold
  double previous = 0.0;  ///< the force a step ago
  double largest_drop = 0.0;  ///< the largest fall of the force from one step to the next, N
  int max_inverted = 0;
  const int steps = scene.num_steps();
  int step = 0;
  bool timed_out = false;
  for (; step < steps && forces.size() < read_times.size(); ++step) {
    const StepStats stats = stepper.step(step, *body);
    if (!monitor.after_step(step, stats, *body, stepper.constraints())) {
      result.status = CaseStatus::kFail;
      add_note(result, "unstable at step " + std::to_string(step + 1) + ": "
                           + monitor.divergence()->reason);
      break;
    }
    stepper.observe(step, *body);
    max_inverted = std::max(max_inverted, count_inverted_tets(mesh.body, body->positions()));
    const double force = 4.0 * stepper.loading().tool_force_vector().z();
    largest_drop = std::max(largest_drop, previous - force);
    // Half a step of slack: the step ending at a read time is that time's.
    const double end = (step + 1) * scene.dt;
    if (holds_begun < hold_times.size() && end > hold_times[holds_begun] + 0.5 * scene.dt) {
      ++holds_begun;  // this step is the hold's first
      hold_steps = 0;
    }
    if (holds_begun > forces.size()) {
      if (++hold_steps >= 3) {
        const double mean = 0.5 * (force + previous);
        hold_low[forces.size()] = std::min(hold_low[forces.size()], mean);
        hold_high[forces.size()] = std::max(hold_high[forces.size()], mean);
      }
    }
    previous = force;
    if (end > read_times[forces.size()] - 0.5 * scene.dt) {
      forces.push_back(force);
    }
    if (run.seconds() > settings.max_wall_seconds) {
      timed_out = forces.size() < read_times.size();
      break;
    }
  }
  if (timed_out) {
    result.status = CaseStatus::kFail;
    add_note(result, "wall-clock budget of " + short_number(settings.max_wall_seconds)
                         + " s spent after " + std::to_string(step + 1) + " steps");
  }

  nlohmann::json depths = nlohmann::json::array();
  double deepest_ratio = kNaN;
  for (std::size_t i = 0; i < settings.depths.size(); ++i) {
    const double depth = settings.depths[i] * settings.sphere_radius;
    const double hertz = 4.0 / 3.0 * modulus * std::sqrt(radius) * std::pow(depth, 1.5);
    const double force = i < forces.size() ? forces[i] : kNaN;
    const double ratio = force / hertz;
    depths.push_back({{"depth_over_radius", settings.depths[i]},
                      {"depth_m", depth},
                      {"contact_radius_m", std::sqrt(radius * depth)},
                      {"force_n", number_or_null(force)},
                      {"hertz_force_n", hertz},
                      {"ratio", number_or_null(ratio)}});
    if (i + 1 == settings.depths.size()) {
      deepest_ratio = ratio;
    } else {
      result.measures.push_back({"ratio_at_" + short_number(settings.depths[i]) + "R", ratio,
                                 1.0, verify_tolerance::kHertz, "force / Hertz's force"});
    }
  }
  result.measures.insert(result.measures.begin(),
                         Measure{"force_ratio", deepest_ratio, 1.0, verify_tolerance::kHertz,
                                 "force / Hertz's force at the deepest point"});
  // A quasi-static press: the force only grows while the sphere goes down and stays put while
  // it holds still.
  double hold_drift = forces.size() == read_times.size() ? 0.0 : kNaN;
  for (std::size_t i = 0; i < forces.size(); ++i) {
    if (hold_high[i] >= hold_low[i]) {
      hold_drift = std::max(hold_drift, (hold_high[i] - hold_low[i]) / forces[i]);
    }
  }
  const double deepest_force = forces.empty() ? kNaN : forces.back();
  result.measures.push_back({"hold_drift", hold_drift, 0.0, verify_tolerance::kHertzHoldDrift,
                             "range of the force's two-step mean over a hold / the force"});
  result.measures.push_back({"inverted_tets", static_cast<double>(max_inverted), 0.0, 0.0,
                             "the most tets inverted at once"});
  result.measures.push_back({"largest_drop", largest_drop / deepest_force, 0.0,
                             verify_tolerance::kHertzDrop,
                             "largest step-to-step fall of the force / the deepest force"});
  add_note(result, material_law_note(model.name));
  result.details = {{"sphere_radius_m", settings.sphere_radius},
                    {"contact_margin_m", margin},
                    {"effective_radius_m", radius},
                    {"young_modulus_pa", material.young_modulus},
                    {"poisson_ratio", material.poisson_ratio},
                    {"quarter_block_m", {across.back(), across.back(), -bottom}},
                    {"cells", {across.size() - 1, across.size() - 1, zs.size() - 1}},
                    {"finest_spacing_m", fine},
                    {"vertices", mesh.body.num_vertices()},
                    {"tets", mesh.body.num_tets()},
                    {"sphere_triangles", mesh.instrument->num_triangles()},
                    {"steps", step},
                    {"depths", depths}};
  return run.finish();
}

}  // namespace softbench::harness
