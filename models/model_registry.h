// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/material.h"
#include "models/param_table.h"
#include "models/soft_body.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace softbench {

/// Where a model's parameter block came from, for error messages ("scenes/x.json",
/// "/models/mass_spring").
struct ParamSource {
  std::string file = "<parameters>";
  std::string pointer;
};

/// Builds a model: all precomputation happens here. Throws InputError naming `source` for a bad
/// parameter. `params` is the scene's block for this model (null: all defaults).
using ModelFactory = std::function<std::unique_ptr<SoftBody>(const TetMesh& mesh,
                                                             const Material& material,
                                                             const nlohmann::json& params,
                                                             const ParamSource& source)>;

/// What the stability map varies for a model: the material's Young's modulus (the default, for
/// a model whose stiffness follows the material), or a parameter of the model without a unit.
struct StiffnessAxisSpec {
  std::string parameter = "young_modulus";  ///< "young_modulus", or the model parameter's key
  bool material = true;  ///< true: the material's Young's modulus; false: params[parameter]
  /// Parameters set for every map run (e.g. mass_spring: springs derived from E).
  nlohmann::json fixed_params = nlohmann::json::object();
  std::string note = "the material's Young's modulus";  ///< one line for the report
};

/// A parameter `softbench calibrate` fits, searched over [lower, upper] (on a log scale when
/// log_scale: a stiffness spans decades).
struct FittedParameter {
  std::string name;
  double lower = 0.0;
  double upper = 1.0;
  bool log_scale = false;
};

/// How a model whose stiffness is not a material constant is fitted to a reference that
/// follows the material (harness/calibrate/calibration.h). A model with nothing in `fitted`
/// follows the material itself: its block is the tissue already.
struct CalibrationSpec {
  std::vector<FittedParameter> fitted;
  /// Set on the block before fitting, over the scene's values (mass_spring: springs from E).
  nlohmann::json fixed = nlohmann::json::object();
  /// The block entries that give the model the reference's Rayleigh mass damping (alpha, 1/s)
  /// at time step dt, so the fitted model is damped as the tissue is. Empty: the model has no
  /// damping to match (shape matching's pull damps by itself).
  std::function<nlohmann::json(double alpha, double dt)> matched_damping;
};

/// Everything the harness needs to know about a model: a new model declares it here, in its own
/// folder, and touches nothing in harness/ or scenes/.
struct ModelInfo {
  std::string name;     ///< the key used in scenes and on the CLI, e.g. "mass_spring"
  std::string summary;  ///< one line for `softbench models`
  std::vector<ParameterDoc> parameters;
  ModelFactory create;
  /// A converged reference (slow): runs only when named, or as the reference of a sweep or an
  /// accuracy requirement.
  bool reference = false;
  StiffnessAxisSpec stiffness_axis;
  /// Parameters that damp a run meant only to reach a static equilibrium (calibration), set
  /// where the scene's block sets none (or zero): the equilibrium does not depend on them, and
  /// the run gets there sooner. Empty: the model has no damping to add.
  nlohmann::json settling_damping = nlohmann::json::object();
  /// The parameter holding the model's Rayleigh mass damping (1/s; "" if it has none): what a
  /// model fitted to this one as a reference takes over (CalibrationSpec::matched_damping).
  std::string mass_damping;
  CalibrationSpec calibration;
  /// Settings that trade accuracy for speed (each merged over the scene's block), cheapest
  /// last: what compare's equal-accuracy chart tries besides the defaults, at the scene's dt and
  /// twice it.
  std::vector<nlohmann::json> speed_settings;
};

/// The models a build knows, by name. Explicit registration (builtin_models.cpp), not static
/// self-registration: a linker drops unreferenced objects from a static library, and the
/// explicit list is greppable and testable.
class ModelRegistry {
 public:
  void add(ModelInfo info);  ///< throws std::logic_error on a duplicate
  /// A model this build leaves out (e.g. Bullet's without SOFTBENCH_WITH_BULLET): scenes may
  /// still carry its parameter block, and asking for it names `reason`.
  void add_unavailable(std::string name, std::string reason);
  bool unavailable(std::string_view name) const;
  const ModelInfo& at(std::string_view name) const;  ///< throws InputError listing known names
  bool contains(std::string_view name) const;
  std::vector<std::string> names() const;  ///< sorted; drives tests, benchmarks and the CLI
  /// names() less the references: what runs when no model is named.
  std::vector<std::string> default_names() const;

 private:
  std::map<std::string, ModelInfo, std::less<>> models_;
  std::map<std::string, std::string, std::less<>> unavailable_;
};

/// Every model of this build, registered once (models/builtin_models.cpp).
const ModelRegistry& builtin_models();

}  // namespace softbench
