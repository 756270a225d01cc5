// SPDX-License-Identifier: MIT
#include "harness/verify/case_support.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "geometry/shape_meshes.h"
#include "harness/run/run_monitor.h"
#include "models/model_registry.h"

#include <omp.h>

#include <cmath>
#include <sstream>

namespace softbench::harness::verify_detail {

nlohmann::json material_params(const ModelUnderTest& model) {
  const ModelInfo& info = builtin_models().at(model.name);
  nlohmann::json params = nlohmann::json::object();
  if (info.stiffness_axis.material) {
    params.update(info.stiffness_axis.fixed_params);
  }
  if (model.params.is_object()) {
    params.update(model.params);
  }
  return params;
}

nlohmann::json static_params(const ModelUnderTest& model) {
  nlohmann::json params = material_params(model);
  for (const auto& [key, value] : builtin_models().at(model.name).settling_damping.items()) {
    if (!params.contains(key) || params[key] == 0.0) {
      params[key] = value;
    }
  }
  return params;
}

std::string material_law_note(const std::string& model) {
  const StiffnessAxisSpec& axis = builtin_models().at(model).stiffness_axis;
  if (axis.material) {
    return "";
  }
  return "its stiffness is not the material's E (" + axis.parameter
         + "): an elastic solution is not what it is made to match";
}

std::unique_ptr<SoftBody> build(const ModelUnderTest& model,
                                const TetMesh& mesh,
                                const Material& material,
                                const nlohmann::json& params,
                                const std::string& case_name) {
  return builtin_models().at(model.name).create(
      mesh, material, params, {"softbench verify (" + case_name + ")", "/models/" + model.name});
}

SettleOutcome settle(SoftBody& body,
                     const TetMesh& mesh,
                     std::span<const PositionConstraint> constraints,
                     const Eigen::Vector3d& gravity,
                     const VerifySettings& settings) {
  RunMonitor monitor(mesh, scenes::StabilityLimits{}, bounding_box_diagonal(mesh.rest_positions()));
  StepInput input;
  input.gravity = gravity;
  input.constraints = constraints;
  SettleOutcome outcome;
  const Stopwatch watch;
  int calm = 0;
  for (int step = 0; step < settings.max_settle_steps; ++step) {
    outcome.steps = step + 1;
    if (!monitor.after_step(step, body.step(settings.dt, input), body, constraints)) {
      outcome.stable = false;
      outcome.failure = monitor.divergence()->reason;
      return outcome;
    }
    calm = monitor.free_speed() < settings.settle_speed * monitor.diagonal() ? calm + 1 : 0;
    if (calm >= settings.settle_steps) {
      outcome.settled = true;
      return outcome;
    }
    if (watch.seconds() > settings.max_wall_seconds) {
      outcome.timed_out = true;
      return outcome;
    }
  }
  return outcome;
}

void add_note(CaseResult& result, const std::string& note) {
  if (note.empty()) {
    return;
  }
  result.note += (result.note.empty() ? "" : "; ") + note;
}

void judge(CaseResult& result) {
  if (result.status != CaseStatus::kPass) {
    return;  // failed already (a blow-up), or set not applicable by the case
  }
  bool any = false;
  bool all = true;
  for (const Measure& measure : result.measures) {
    if (measure.judged()) {
      any = true;
      all = all && measure.passes();
    }
  }
  if (!any) {
    result.status = CaseStatus::kNotApplicable;
  } else if (!all) {
    result.status = CaseStatus::kFail;
  }
}

bool record_outcome(CaseResult& result, const SettleOutcome& outcome, const std::string& what) {
  const std::string prefix = what.empty() ? "" : what + ": ";
  if (!outcome.stable) {
    result.status = CaseStatus::kFail;
    add_note(result, prefix + "unstable at step " + std::to_string(outcome.steps) + ": "
                         + outcome.failure);
    return false;
  }
  if (outcome.timed_out) {
    add_note(result, prefix + "wall-clock budget spent after " + std::to_string(outcome.steps)
                         + " steps, measured there");
  } else if (!outcome.settled) {
    add_note(result, prefix + "still moving after " + std::to_string(outcome.steps)
                         + " steps, measured there");
  }
  return true;
}

OneThread::OneThread() : threads_(omp_get_max_threads()) {
  omp_set_num_threads(1);
}

OneThread::~OneThread() {
  omp_set_num_threads(threads_);
}

const TetMesh& spin_box() {
  static const TetMesh mesh = make_tet_mesh(box_tets(5, 3, 2, 0.10, 0.06, 0.04));
  return mesh;
}

std::string short_number(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

}  // namespace softbench::harness::verify_detail
