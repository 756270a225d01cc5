// SPDX-License-Identifier: MIT
#include "harness/verify/verify.h"

#include "geometry/input_error.h"
#include "harness/verify/case_support.h"
#include "models/model_registry.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <map>

namespace softbench::harness {

std::string to_string(CaseStatus status) {
  switch (status) {
    case CaseStatus::kPass:
      return "pass";
    case CaseStatus::kFail:
      return "fail";
    case CaseStatus::kNotApplicable:
      return "n/a";
  }
  return "?";
}

bool Measure::passes() const {
  return tolerance && std::isfinite(value) && std::abs(value - target) <= *tolerance;
}

VerifySettings default_verify_settings() {
  return VerifySettings{};
}

VerifySettings quick_verify_settings() {
  VerifySettings settings;
  settings.quick = true;
  settings.max_wall_seconds = 20.0;
  settings.patch_cells = 3;
  settings.rigid_steps = 30;
  settings.beam_levels = {2, 4};  // the finest level judged is the full run's
  // A coarser block: half the cells across the contact, faster growth, a smaller sphere mesh.
  settings.fine_spacing = 0.3;
  settings.growth = 1.5;
  settings.block_side = 8.0;
  settings.block_depth = 4.0;
  settings.sphere_levels = 3;
  settings.ramp_seconds = 0.2;
  settings.hold_seconds = 0.15;
  settings.spin.duration = 1.0;
  settings.recovery_window = 2.0;
  return settings;
}

namespace {

using CaseFunction = CaseResult (*)(const ModelUnderTest&, const VerifySettings&);

const std::vector<std::pair<std::string, CaseFunction>>& cases() {
  static const std::vector<std::pair<std::string, CaseFunction>> table{
      {"patch", patch_case},
      {"rigid_motion", rigid_motion_case},
      {"cantilever", cantilever_case},
      {"hertz", hertz_case},
      {"free_spin", free_spin_case},
      {"squash_release", squash_release_case},
  };
  return table;
}

std::string join(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) {
    joined += (joined.empty() ? "" : ", ") + name;
  }
  return joined;
}

}  // namespace

const std::vector<std::string>& verify_case_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> result;
    for (const auto& [name, function] : cases()) {
      result.push_back(name);
    }
    return result;
  }();
  return names;
}

CaseResult run_case(const std::string& name,
                    const ModelUnderTest& model,
                    const VerifySettings& settings) {
  for (const auto& [key, function] : cases()) {
    if (key == name) {
      return function(model, settings);
    }
  }
  throw InputError("unknown verification case \"" + name + "\" (known: "
                   + join(verify_case_names()) + ")");
}

VerifyReport run_verify(const VerifyOptions& options) {
  const verify_detail::Stopwatch watch;
  const std::vector<std::string> models =
      options.models.empty() ? builtin_models().default_names() : options.models;
  for (const std::string& name : models) {
    if (!builtin_models().contains(name)) {
      try {
        builtin_models().at(name);
      } catch (const InputError& error) {
        throw InputError("--model " + name + ": " + error.what());
      }
    }
  }
  const std::vector<std::string>& case_names =
      options.cases.empty() ? verify_case_names() : options.cases;
  for (const std::string& name : case_names) {
    if (std::find(verify_case_names().begin(), verify_case_names().end(), name)
        == verify_case_names().end()) {
      throw InputError("unknown verification case \"" + name + "\" (known: "
                       + join(verify_case_names()) + ")");
    }
  }
  VerifyReport report;
  report.settings = options.settings;
  for (const std::string& name : models) {
    const verify_detail::Stopwatch model_watch;
    ModelVerification verification;
    verification.model = name;
    for (const std::string& case_name : case_names) {
      CaseResult result = run_case(case_name, {name, nlohmann::json::object()}, options.settings);
      if (options.progress != nullptr) {
        *options.progress << name << " " << case_name << ": " << to_string(result.status);
        if (!result.measures.empty()) {
          *options.progress << " (" << result.measures.front().name << " "
                            << verify_detail::short_number(result.measures.front().value) << ")";
        }
        *options.progress << ", " << std::fixed << std::setprecision(2) << result.seconds
                          << " s\n"
                          << std::defaultfloat;
      }
      verification.cases.push_back(std::move(result));
    }
    verification.seconds = model_watch.seconds();
    report.models.push_back(std::move(verification));
  }
  report.wall_seconds = watch.seconds();
  return report;
}

}  // namespace softbench::harness
