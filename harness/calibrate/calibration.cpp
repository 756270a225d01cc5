// SPDX-License-Identifier: MIT
#include "harness/calibrate/calibration.h"

#include "harness/format.h"
#include "geometry/atomic_file.h"
#include "geometry/input_error.h"
#include "harness/provenance.h"
#include "models/json_file.h"
#include "models/model_registry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

namespace softbench::harness {
namespace {

/// Bumped when what a calibration computes changes, so old caches are not read as new.
constexpr int kCalibrationVersion = 2;

/// What of the scene the tissue's response depends on: not its name, script, duration or other
/// models' blocks, so every scene of the same tissue, mesh and tool shares one calibration.
nlohmann::json tissue_key(const scenes::Scene& scene,
                          const SceneMesh& mesh,
                          const CalibrationOptions& options) {
  const nlohmann::json full = scenes::to_json(scene);
  std::ostringstream tool;
  tool << std::setprecision(17);
  if (mesh.instrument != nullptr) {
    tool << mesh.instrument->vertices.transpose() << mesh.instrument->triangles.transpose();
  }
  nlohmann::json key = {{"version", kCalibrationVersion},
                        {"material", full["material"]},
                        {"gravity", full["gravity"]["acceleration"]},
                        {"dt", scene.dt},
                        {"fixed", full["fixed"]},
                        {"supports", full.value("supports", nlohmann::json::array())},
                        {"limits", full.value("limits", nlohmann::json::object())},
                        {"mesh_hash", mesh.content_hash},
                        {"instrument_hash", stable_hash(tool.str())},
                        {"against", options.against},
                        {"reference_block", scene.parameters_for(options.against)},
                        {"press",
                         {{"depths", options.press.depths},
                          {"approach", options.press.approach},
                          {"speed", options.press.speed},
                          {"overshoot", options.press.overshoot},
                          {"rest_speed", options.press.settling.rest_speed},
                          {"settle_time", options.press.settling.max_time}}},
                        {"build", build_fingerprint()}};
  if (scene.instrument) {
    key["contact_margin"] = scene.instrument->contact_margin;
  }
  return key;
}

std::filesystem::path cache_file(const CalibrationOptions& options,
                                 const std::string& prefix,
                                 const nlohmann::json& key) {
  return options.cache_dir / (prefix + "-" + stable_hash(key.dump()) + ".json");
}

void write_cache(const std::filesystem::path& path, const nlohmann::json& json) {
  std::filesystem::create_directories(path.parent_path());
  const std::string text = json.dump(1) + "\n";
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

/// Added to the cost of a candidate whose run a report would flag (TissueResponse::implausible):
/// more than any plausible candidate's cost (a thousandfold miss on every target is 47.7), so
/// every plausible candidate ranks first and an implausible one wins only when nothing in the
/// range is plausible, and then says so.
constexpr double kImplausible = 1e3;

/// The fit's cost: the mean squared log ratio of the sag and, together with it, of the press
/// forces (sag and press weigh half each). Log ratios treat too stiff and too soft alike; a
/// target the model missed entirely (no sag, no force) counts as a thousandfold miss, one it
/// never reached (it blew up) as infinite.
double cost(const TissueResponse& model, const TissueResponse& reference) {
  if (!model.sag.stable || !model.press_stable) {
    return std::numeric_limits<double>::infinity();
  }
  const auto miss = [](double value, double target) {
    if (!std::isfinite(value)) {
      return std::numeric_limits<double>::infinity();
    }
    const double ratio = std::max(value / target, 1e-3);
    return std::log(ratio) * std::log(ratio);
  };
  const double sag = miss(model.sag.sag, reference.sag.sag);
  if (!model.implausible.empty()) {
    // Its sag, where it has one, still orders the implausible candidates among themselves.
    return kImplausible + (model.sag.implausible.empty() ? sag : kImplausible);
  }
  double press = 0.0;
  for (std::size_t i = 0; i < reference.forces.size(); ++i) {
    press += miss(model.forces[i], reference.forces[i]);
  }
  return reference.forces.empty() ? sag : 0.5 * sag + 0.5 * press / reference.forces.size();
}

std::vector<double> relative_errors(const TissueResponse& model, const TissueResponse& reference) {
  std::vector<double> errors{model.sag.sag / reference.sag.sag - 1.0};
  for (std::size_t i = 0; i < reference.forces.size(); ++i) {
    errors.push_back(model.forces[i] / reference.forces[i] - 1.0);
  }
  return errors;
}

double value_at(const FittedParameter& parameter, double u) {
  return parameter.log_scale
             ? parameter.lower * std::pow(parameter.upper / parameter.lower, u)
             : parameter.lower + u * (parameter.upper - parameter.lower);
}

/// Minimises `evaluate` over the unit cube (one coordinate per fitted parameter): the best point
/// of a coarse grid (7 points for one parameter, 4 x 4 for two), then a golden-section search
/// along each coordinate in turn within the grid cells around the best point so far.
/// Deterministic: the same points in the same order every time.
class Search {
 public:
  Search(int dimensions, std::function<double(const std::vector<double>&)> evaluate)
      : dimensions_(dimensions), evaluate_(std::move(evaluate)) {}

  std::vector<double> run() {
    const int per_axis = dimensions_ == 1 ? 7 : 4;
    const double cell = 1.0 / (per_axis - 1);
    std::vector<int> index(static_cast<std::size_t>(dimensions_), 0);
    while (true) {
      std::vector<double> u;
      for (int i : index) {
        u.push_back(i * cell);
      }
      consider(u);
      std::size_t axis = 0;
      while (axis < index.size() && ++index[axis] == per_axis) {
        index[axis++] = 0;
      }
      if (axis == index.size()) {
        break;
      }
    }
    const int iterations = dimensions_ == 1 ? 12 : 7;
    for (int axis = 0; axis < dimensions_; ++axis) {
      golden(axis, std::max(0.0, best_[axis] - cell), std::min(1.0, best_[axis] + cell),
             iterations);
    }
    return best_;
  }

  double best_cost() const { return best_cost_; }

 private:
  double consider(const std::vector<double>& u) {
    const auto known = seen_.find(u);
    if (known != seen_.end()) {
      return known->second;
    }
    const double value = evaluate_(u);
    seen_.emplace(u, value);
    if (value < best_cost_ || best_.empty()) {
      best_cost_ = value;
      best_ = u;
    }
    return value;
  }

  void golden(int axis, double lo, double hi, int iterations) {
    const std::vector<double> origin = best_;
    const auto at = [&](double t) {
      std::vector<double> u = origin;
      u[static_cast<std::size_t>(axis)] = t;
      return consider(u);
    };
    const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
    double a = hi - ratio * (hi - lo);
    double b = lo + ratio * (hi - lo);
    double fa = at(a);
    double fb = at(b);
    for (int k = 0; k < iterations; ++k) {
      if (fa <= fb) {
        hi = b;
        b = a;
        fb = fa;
        a = hi - ratio * (hi - lo);
        fa = at(a);
      } else {
        lo = a;
        a = b;
        fa = fb;
        b = lo + ratio * (hi - lo);
        fb = at(b);
      }
    }
  }

  int dimensions_;
  std::function<double(const std::vector<double>&)> evaluate_;
  std::map<std::vector<double>, double> seen_;
  std::vector<double> best_;
  double best_cost_ = std::numeric_limits<double>::infinity();
};

std::string target_name(double depth) {
  std::ostringstream out;
  out << "force at " << 100.0 * depth << " cm";
  return out.str();
}

nlohmann::json to_json(const Calibration& calibration) {
  return {{"model", calibration.model},
          {"against", calibration.against},
          {"reference", to_json(calibration.reference)},
          {"fitted", to_json(calibration.fitted)},
          {"params", calibration.params},
          {"values", calibration.values},
          {"targets", calibration.targets},
          {"errors", calibration.errors},
          {"objective", calibration.objective},
          {"evaluations", calibration.evaluations},
          {"seconds", calibration.seconds},
          {"reference_seconds", calibration.reference_seconds}};
}

Calibration calibration_from_json(const nlohmann::json& json) {
  Calibration calibration;
  calibration.model = json.at("model").get<std::string>();
  calibration.against = json.at("against").get<std::string>();
  calibration.reference = tissue_response_from_json(json.at("reference"));
  calibration.fitted = tissue_response_from_json(json.at("fitted"));
  calibration.params = json.at("params");
  calibration.values = json.at("values");
  calibration.targets = json.at("targets").get<std::vector<std::string>>();
  calibration.errors = json.at("errors").get<std::vector<double>>();
  calibration.objective = json.at("objective").get<double>();
  calibration.evaluations = json.at("evaluations").get<int>();
  calibration.seconds = json.at("seconds").get<double>();
  calibration.reference_seconds = json.at("reference_seconds").get<double>();
  calibration.cached = true;
  return calibration;
}

}  // namespace

std::string format_cm(double metres) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3) << 100.0 * metres << " cm";
  return out.str();
}

bool calibratable(const std::string& model) {
  return !builtin_models().at(model).calibration.fitted.empty();
}

TissueResponse reference_response(const scenes::Scene& scene,
                                  const SceneMesh& mesh,
                                  const CalibrationOptions& options,
                                  double* seconds) {
  const nlohmann::json key = tissue_key(scene, mesh, options);
  const std::filesystem::path cache = cache_file(options, "reference", key);
  if (!options.cache_dir.empty() && std::filesystem::exists(cache)) {
    const nlohmann::json json = read_json_file(cache);
    if (seconds != nullptr) {
      *seconds = json.at("response").at("seconds").get<double>();
    }
    return tissue_response_from_json(json.at("response"));
  }
  const TissueResponse response = tissue_response(
      scene, mesh, options.against, scene.parameters_for(options.against), options.press);
  if (!response.sag.stable || !response.press_stable || !response.implausible.empty()) {
    const std::string why = response.implausible.empty()
                                ? "blew up under gravity or in the press"
                                : "left a tissue's state: " + response.implausible;
    throw InputError(scene.source.string() + ": the reference " + options.against + " " + why
                     + "; nothing to calibrate against");
  }
  for (double force : response.forces) {
    if (!(force > 0.0)) {
      throw InputError(scene.source.string() + ": the reference " + options.against
                       + " felt no force in the press; nothing to calibrate against");
    }
  }
  if (options.progress != nullptr) {
    *options.progress << options.against << ": sag " << format_cm(response.sag.sag)
                      << ", press forces";
    for (double force : response.forces) {
      *options.progress << " " << force << " N";
    }
    *options.progress << " (" << response.seconds << " s)\n";
  }
  if (!options.cache_dir.empty()) {
    write_cache(cache, {{"key", key}, {"response", to_json(response)}});
  }
  if (seconds != nullptr) {
    *seconds = response.seconds;
  }
  return response;
}

Calibration calibrate(const scenes::Scene& scene,
                      const SceneMesh& mesh,
                      const std::string& model,
                      const CalibrationOptions& options) {
  const ModelInfo& info = builtin_models().at(model);
  const ModelInfo& reference_info = builtin_models().at(options.against);
  if (info.calibration.fitted.empty()) {
    throw InputError("calibrate: --model " + model
                     + ": its stiffness follows the material; nothing to fit");
  }
  // The block every candidate starts from: the scene's, the declared fixed values, and the
  // reference's mass damping in the model's own terms.
  nlohmann::json base = scene.parameters_for(model);
  if (base.is_null()) {
    base = nlohmann::json::object();
  }
  base.erase("calibrated");
  base.update(info.calibration.fixed);
  const ParamSource source{scene.source.string(), "/models/" + model};
  if (info.calibration.matched_damping && !reference_info.mass_damping.empty()) {
    const nlohmann::json reference_params =
        reference_info.create(mesh.body, scene.material, scene.parameters_for(options.against),
                              {scene.source.string(), "/models/" + options.against})
            ->parameters();
    base.update(info.calibration.matched_damping(
        reference_params.at(reference_info.mass_damping).get<double>(), scene.dt));
  }

  nlohmann::json key = tissue_key(scene, mesh, options);
  key["model"] = model;
  key["base"] = base;
  for (const FittedParameter& parameter : info.calibration.fitted) {
    key["fitted"].push_back(
        {parameter.name, parameter.lower, parameter.upper, parameter.log_scale});
  }
  const std::filesystem::path cache = cache_file(options, model, key);
  if (!options.cache_dir.empty() && std::filesystem::exists(cache)) {
    return calibration_from_json(read_json_file(cache).at("calibration"));
  }

  Calibration result;
  result.model = model;
  result.against = options.against;
  result.reference = reference_response(scene, mesh, options, &result.reference_seconds);
  result.targets.push_back("sag");
  for (double depth : options.press.depths) {
    result.targets.push_back(target_name(depth));
  }

  const auto started = std::chrono::steady_clock::now();
  const std::vector<FittedParameter>& fitted = info.calibration.fitted;
  const auto block_at = [&](const std::vector<double>& u) {
    nlohmann::json block = base;
    for (std::size_t i = 0; i < fitted.size(); ++i) {
      block[fitted[i].name] = value_at(fitted[i], u[i]);
    }
    return block;
  };
  std::map<std::vector<double>, TissueResponse> responses;
  Search search(static_cast<int>(fitted.size()), [&](const std::vector<double>& u) {
    const nlohmann::json block = block_at(u);
    TissueResponse response = tissue_response(scene, mesh, model, block, options.press);
    ++result.evaluations;
    const double value = cost(response, result.reference);
    if (options.progress != nullptr) {
      *options.progress << model;
      for (const FittedParameter& parameter : fitted) {
        *options.progress << " " << parameter.name << " " << block[parameter.name].get<double>();
      }
      *options.progress << ": sag " << format_cm(response.sag.sag) << ", forces";
      for (double force : response.forces) {
        *options.progress << " " << force;
      }
      *options.progress << " N, cost " << value << " (at rest after " << response.sag.time
                        << " s; " << response.seconds << " s)";
      if (!response.implausible.empty()) {
        *options.progress << "; not a tissue's: " << response.implausible;
      }
      *options.progress << "\n";
    }
    response.sag.positions.resize(3, 0);  // the targets are kept, not every candidate's shape
    responses.emplace(u, std::move(response));
    return value;
  });
  const std::vector<double> best = search.run();
  result.seconds = seconds_since(started);
  result.objective = search.best_cost();
  result.fitted = responses.at(best);
  result.errors = relative_errors(result.fitted, result.reference);
  if (!std::isfinite(result.objective)) {
    throw InputError(scene.source.string() + ": " + model
                     + " blew up at every point of its calibration range");
  }
  if (!result.fitted.sag.implausible.empty()) {
    throw InputError(scene.source.string() + ": " + model
                     + " crumpled under gravity at every point of its calibration range ("
                     + result.fitted.sag.implausible + " at best)");
  }

  nlohmann::json block = block_at(best);
  result.values = nlohmann::json::object();
  for (const FittedParameter& parameter : fitted) {
    result.values[parameter.name] = block[parameter.name];
  }
  CalibrationRecord record;
  record.against = options.against;
  record.dt = scene.dt;
  record.sag = result.reference.sag.sag;
  record.depths = options.press.depths;
  record.forces = result.reference.forces;
  record.errors = result.errors;
  block["calibrated"] = to_json(std::optional<CalibrationRecord>(record));
  // The effective block (defaults filled in), as the model echoes it.
  result.params = info.create(mesh.body, scene.material, block, source)->parameters();
  if (!options.cache_dir.empty()) {
    write_cache(cache, {{"key", key}, {"calibration", to_json(result)}});
  }
  return result;
}

nlohmann::json scene_with_block(nlohmann::json scene_json,
                                const std::filesystem::path& scene_file,
                                const std::filesystem::path& folder,
                                const std::string& model,
                                const nlohmann::json& block) {
  const std::filesystem::path from = scene_file.parent_path();
  const auto rebase = [&](nlohmann::json& path) {
    if (!path.is_string()) {
      return;
    }
    const std::filesystem::path written = path.get<std::string>();
    if (written.is_absolute()) {
      return;
    }
    const std::filesystem::path absolute = std::filesystem::weakly_canonical(from / written);
    const std::filesystem::path relative =
        absolute.lexically_relative(std::filesystem::weakly_canonical(folder));
    path = (relative.empty() ? absolute : relative).generic_string();
  };
  if (scene_json.contains("mesh")) {
    rebase(scene_json["mesh"]);
  }
  if (scene_json.contains("instrument") && scene_json["instrument"].is_object()
      && scene_json["instrument"].contains("mesh")) {
    rebase(scene_json["instrument"]["mesh"]);
  }
  scene_json["models"][model] = block;
  return scene_json;
}

}  // namespace softbench::harness
