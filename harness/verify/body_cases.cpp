// SPDX-License-Identifier: MIT
// The verification cases on a body alone (no instrument): patch, rigid motion, cantilever, free
// spin, squash and release.
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "geometry/shape_meshes.h"
#include "harness/format.h"
#include "harness/run/run_monitor.h"
#include "harness/stability/stability_run.h"
#include "harness/stability/torture_shapes.h"
#include "harness/verify/case_support.h"
#include "harness/verify/free_spin.h"
#include "harness/verify/verify.h"
#include "harness/verify/verify_tolerances.h"
#include "models/model_registry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace softbench::harness {

using namespace verify_detail;

namespace {


/// Vertices on the box's faces (within a hair of its bounding box).
std::vector<char> on_boundary(const Eigen::Matrix3Xd& rest) {
  const Eigen::Vector3d low = rest.rowwise().minCoeff();
  const Eigen::Vector3d high = rest.rowwise().maxCoeff();
  const double hair = 1e-9 * (high - low).norm();
  std::vector<char> boundary(static_cast<std::size_t>(rest.cols()), 0);
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      if (rest(axis, v) <= low(axis) + hair || rest(axis, v) >= high(axis) - hair) {
        boundary[static_cast<std::size_t>(v)] = 1;
      }
    }
  }
  return boundary;
}

/// Exact pins on the vertices with x <= min x (+ a hair), at rest.
std::vector<int> min_x_face(const TetMesh& mesh) {
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const double min_x = rest.row(0).minCoeff();
  const double hair = 1e-9 * bounding_box_diagonal(rest);
  std::vector<int> face;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (rest(0, v) <= min_x + hair) {
      face.push_back(v);
    }
  }
  return face;
}

std::vector<PositionConstraint> pinned_at_rest(const TetMesh& mesh, const std::vector<int>& which) {
  std::vector<PositionConstraint> pins;
  for (const int v : which) {
    pins.push_back({v, mesh.rest_positions().col(v), kExact});
  }
  return pins;
}

}  // namespace

CaseResult patch_case(const ModelUnderTest& model, const VerifySettings& settings) {
  CaseRun run("patch");
  CaseResult& result = run.result;
  const double size = settings.patch_size;
  const int n = settings.patch_cells;
  const TetMesh mesh = make_tet_mesh(box_tets(n, n, n, size, size, size));
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  // A general uniform strain: stretch, compression, shear and a rotation part, the largest entry
  // settings.patch_strain.
  Eigen::Matrix3d gradient;
  gradient << 1.0, 0.3, -0.2,  //
      0.1, -0.5, 0.4,          //
      0.25, 0.15, 0.7;
  gradient *= settings.patch_strain;
  const Eigen::Vector3d centre = Eigen::Vector3d::Constant(0.5 * size);
  const auto affine = [&](Eigen::Index v) -> Eigen::Vector3d {
    return rest.col(v) + gradient * (rest.col(v) - centre);
  };

  const std::vector<char> boundary = on_boundary(rest);
  std::vector<PositionConstraint> pins;
  double imposed = 0.0;
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    if (boundary[static_cast<std::size_t>(v)] != 0) {
      pins.push_back({static_cast<int>(v), affine(v), kExact});
      imposed = std::max(imposed, (affine(v) - rest.col(v)).norm());
    }
  }
  const std::unique_ptr<SoftBody> body =
      build(model, mesh, settings.material, static_params(model), result.name);
  const SettleOutcome outcome =
      settle(*body, mesh, pins, Eigen::Vector3d::Zero(), settings);
  double error = kNaN;
  if (record_outcome(result, outcome)) {
    error = 0.0;
    for (Eigen::Index v = 0; v < rest.cols(); ++v) {
      if (boundary[static_cast<std::size_t>(v)] == 0) {
        error = std::max(error, (body->positions().col(v) - affine(v)).norm());
      }
    }
    error /= imposed;
  }
  result.measures.push_back({"interior_error", error, 0.0, verify_tolerance::kPatch,
                             "largest interior distance from the affine field / largest "
                             "imposed displacement"});
  result.details = {{"vertices", mesh.num_vertices()},
                    {"tets", mesh.num_tets()},
                    {"interior_vertices", mesh.num_vertices() - static_cast<int>(pins.size())},
                    {"imposed_displacement_m", imposed},
                    {"steps", outcome.steps},
                    {"settled", outcome.settled}};
  return run.finish();
}

CaseResult rigid_motion_case(const ModelUnderTest& model, const VerifySettings& settings) {
  CaseRun run("rigid_motion");
  CaseResult& result = run.result;
  const TetMesh& mesh = spin_box();
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  const double diagonal = bounding_box_diagonal(rest);
  const Eigen::Vector3d centre = rest.rowwise().mean();
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.5 * std::numbers::pi, Eigen::Vector3d(1.0, 2.0, 3.0).normalized())
          .toRotationMatrix();
  const Eigen::Vector3d translation(0.03, -0.02, 0.05);
  const Eigen::Matrix3Xd placed =
      ((rotation * (rest.colwise() - centre)).colwise() + centre).colwise() + translation;

  const std::unique_ptr<SoftBody> body =
      build(model, mesh, settings.material, material_params(model), result.name);
  // The body starts in the moved shape at rest: a strain-free state it must keep.
  body->set_state(placed, Eigen::Matrix3Xd::Zero(3, rest.cols()));
  RunMonitor monitor(mesh, scenes::StabilityLimits{}, diagonal);
  StepInput input;
  input.gravity.setZero();
  double displacement = 0.0;
  int steps = 0;
  for (; steps < settings.rigid_steps; ++steps) {
    if (!monitor.after_step(steps, body->step(settings.dt, input), *body, {})) {
      result.status = CaseStatus::kFail;
      add_note(result, "unstable at step " + std::to_string(steps + 1) + ": "
                           + monitor.divergence()->reason);
      displacement = kNaN;
      break;
    }
    displacement = std::max(
        displacement, (body->positions() - placed).colwise().norm().maxCoeff() / diagonal);
  }
  result.measures.push_back({"max_displacement", displacement, 0.0,
                             verify_tolerance::kRigidDisplacement,
                             "largest vertex distance from the moved rest shape / bbox diagonal"});
  const double energy = body->elastic_energy();
  const double scale = settings.material.young_modulus * mesh_volume(mesh, rest);
  if (std::isfinite(energy) || result.status == CaseStatus::kFail) {
    result.measures.push_back({"elastic_energy", energy / scale, 0.0,
                               verify_tolerance::kRigidEnergy,
                               "elastic energy after the steps / (E x volume)"});
  } else {
    result.measures.push_back({"elastic_energy", kNaN, 0.0, std::nullopt,
                               "the model has no elastic energy"});
    add_note(result, "no elastic energy: judged on the displacement alone");
  }
  result.details = {{"vertices", mesh.num_vertices()},
                    {"tets", mesh.num_tets()},
                    {"rotation_deg", 90.0},
                    {"axis", {1.0, 2.0, 3.0}},
                    {"translation_m", {translation.x(), translation.y(), translation.z()}},
                    {"steps", steps}};
  return run.finish();
}

CaseResult cantilever_case(const ModelUnderTest& model, const VerifySettings& settings) {
  CaseRun run("cantilever");
  CaseResult& result = run.result;
  const double length = settings.beam_length;
  const double side = settings.beam_side;
  const Material& material = settings.beam_material;
  const double g = 9.81;
  // Euler-Bernoulli, uniform load w = rho g A on a clamped beam: delta = w L^4 / (8 E I).
  const double young = settings.analytic_young_modulus.value_or(material.young_modulus);
  const double load = material.density * g * side * side;
  const double inertia = side * side * side * side / 12.0;
  const double analytic = load * std::pow(length, 4) / (8.0 * young * inertia);

  nlohmann::json levels = nlohmann::json::array();
  std::vector<double> errors;
  bool blew_up = false;
  for (const int across : settings.beam_levels) {
    const Stopwatch level_watch;
    const int along = std::max(1, static_cast<int>(std::lround(across * length / side)));
    const TetMesh mesh = make_tet_mesh(box_tets(along, across, across, length, side, side));
    const std::vector<PositionConstraint> pins = pinned_at_rest(mesh, min_x_face(mesh));
    const std::unique_ptr<SoftBody> body =
        build(model, mesh, material, static_params(model), result.name);
    const SettleOutcome outcome =
        settle(*body, mesh, pins, Eigen::Vector3d(0.0, 0.0, -g), settings);
    double deflection = kNaN;
    if (record_outcome(result, outcome,
                       "level " + std::to_string(levels.size() + 1) + " (" + std::to_string(across)
                           + " cells across)")) {
      // The tip face's mean vertical displacement: its centroid's, the beam axis's deflection.
      double sum = 0.0;
      int count = 0;
      const Eigen::Matrix3Xd& rest = mesh.rest_positions();
      for (Eigen::Index v = 0; v < rest.cols(); ++v) {
        if (rest(0, v) >= length * (1.0 - 1e-9)) {
          sum += rest(2, v) - body->positions()(2, v);
          ++count;
        }
      }
      deflection = sum / count;
    } else {
      blew_up = true;
    }
    const double error = std::abs(deflection / analytic - 1.0);
    errors.push_back(error);
    levels.push_back({{"cells", {along, across, across}},
                      {"vertices", mesh.num_vertices()},
                      {"tets", mesh.num_tets()},
                      {"tip_deflection_m", number_or_null(deflection)},
                      {"error", number_or_null(error)},
                      {"steps", outcome.steps},
                      {"settled", outcome.settled},
                      {"seconds", level_watch.seconds()}});
    if (blew_up) {
      break;  // a finer mesh would only blow up later
    }
  }
  const double finest = blew_up || errors.empty() ? kNaN : errors.back();
  result.measures.push_back({"finest_error", finest, 0.0, verify_tolerance::kCantilever,
                             "|tip deflection / Euler-Bernoulli's - 1| at the finest level"});
  // Each level's error below the previous one's: the largest ratio must be below 1.
  double worst_ratio = 0.0;
  for (std::size_t i = 1; i < errors.size(); ++i) {
    worst_ratio = std::max(worst_ratio, errors[i] / errors[i - 1]);
  }
  if (blew_up || errors.size() < 2) {
    worst_ratio = kNaN;
  }
  const bool material_law = material_law_note(model.name).empty();
  result.measures.push_back(
      {"refinement_ratio", worst_ratio, 0.0,
       material_law ? std::optional<double>(1.0) : std::nullopt,
       "largest error(level k+1) / error(level k): below 1 when the error falls with refinement"});
  for (std::size_t i = 0; i < errors.size(); ++i) {
    result.measures.push_back({"error_level_" + std::to_string(i + 1), errors[i], 0.0,
                               std::nullopt, "|tip deflection / Euler-Bernoulli's - 1|"});
  }
  add_note(result, material_law_note(model.name));
  result.details = {{"length_m", length},
                    {"side_m", side},
                    {"young_modulus_pa", material.young_modulus},
                    {"analytic_young_modulus_pa", young},
                    {"poisson_ratio", material.poisson_ratio},
                    {"density", material.density},
                    {"euler_bernoulli_deflection_m", analytic},
                    {"levels", levels}};
  return run.finish();
}

CaseResult free_spin_case(const ModelUnderTest& model, const VerifySettings& settings) {
  CaseRun run("free_spin");
  CaseResult& result = run.result;
  const SpinResult spin = free_spin(model.name, without_damping(model.name, model.params),
                                    spin_box(), settings.material, settings.spin);
  if (!spin.finite) {
    result.status = CaseStatus::kFail;
    add_note(result, "NaN or Inf at step " + std::to_string(spin.steps_run + 1));
  }
  const auto or_nan = [&](double value) { return spin.finite ? value : kNaN; };
  result.measures.push_back({"momentum_drift", or_nan(spin.momentum_drift), 0.0,
                             verify_tolerance::kSpinMomentum,
                             "largest |L(t) - L(0)| / |L(0)|"});
  result.measures.push_back({"shape_error", or_nan(spin.shape_error), 0.0,
                             verify_tolerance::kSpinShape,
                             "largest RMS distance from the rigid fit / bbox diagonal"});
  result.measures.push_back({"centre_drift", or_nan(spin.centre_drift), 0.0, std::nullopt,
                             "largest centre-of-mass displacement / bbox diagonal"});
  result.details = {{"rate_rad_s", settings.spin.rate},
                    {"axis", {settings.spin.axis.x(), settings.spin.axis.y(),
                              settings.spin.axis.z()}},
                    {"duration_s", settings.spin.duration},
                    {"dt_s", settings.spin.dt},
                    {"damping_off", builtin_models().at(model.name).settling_damping},
                    {"steps", spin.steps_run}};
  return run.finish();
}

CaseResult squash_release_case(const ModelUnderTest& model, const VerifySettings& settings) {
  CaseRun run("squash_release");
  CaseResult& result = run.result;
  const TetMesh& mesh = spin_box();
  const std::vector<int> fixed = min_x_face(mesh);
  const std::unique_ptr<SoftBody> body =
      build(model, mesh, settings.material, static_params(model), result.name);
  RunBounds bounds;
  bounds.max_wall_seconds = settings.max_wall_seconds;
  const int steps = static_cast<int>(std::ceil(settings.recovery_window / settings.dt));
  const RunVerdict verdict = run_torture(*body, mesh, fixed,
                                         squashed_to_plane(mesh.rest_positions()), settings.dt,
                                         steps, bounds);
  if (!verdict.stable()) {
    result.status = CaseStatus::kFail;
    add_note(result, to_string(verdict.status) + ": " + verdict.failure);
  }
  result.measures.push_back({"residual", verdict.residual, 0.0, verify_tolerance::kSquashResidual,
                             "RMS distance from the rest shape / bbox diagonal at the end"});
  result.details = {{"vertices", mesh.num_vertices()},
                    {"tets", mesh.num_tets()},
                    {"fixed_vertices", fixed.size()},
                    {"recovery_window_s", settings.recovery_window},
                    {"steps_run", verdict.steps_run},
                    {"max_inverted_tets", verdict.max_inverted_tets},
                    {"final_inverted_tets", verdict.final_inverted_tets}};
  if (verdict.time_to_one_percent) {
    result.details["time_to_one_percent_s"] = *verdict.time_to_one_percent;
  }
  if (verdict.settled_after) {
    result.details["settled_after_s"] = *verdict.settled_after;
  }
  if (verdict.final_inverted_tets > 0) {
    add_note(result, std::to_string(verdict.final_inverted_tets) + " tets still inverted");
  }
  return run.finish();
}

}  // namespace softbench::harness
