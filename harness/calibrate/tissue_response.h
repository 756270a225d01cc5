// SPDX-License-Identifier: MIT
// What a calibration matches: how the scene's body responds as tissue, measured the same way on
// the reference and on the model being fitted. Two targets, together: the static sag of the
// body hanging from the scene's fixed region under the scene's gravity, and the force-depth
// curve of a press by the scene's instrument on the settled body.
#pragma once

#include "harness/run/scene_mesh.h"
#include "scenes/scene.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace softbench::harness {

struct StaticSagOptions {
  /// m/s: at rest once every free vertex stayed slower than this for 1 s of simulated time.
  double rest_speed = 2e-4;
  double max_time = 60.0;  ///< s of simulated time before giving up
};

struct StaticSag {
  double sag = 0.0;      ///< m: mean displacement of the free vertices along gravity
  double time = 0.0;     ///< s of simulated time it took to come to rest
  bool settled = false;  ///< came to rest within max_time
  bool stable = true;    ///< RunMonitor's rule held at every step
  /// Why the body is not a tissue's (a run's report would flag it: more tets inverted at once
  /// or more volume change than PlausibilityLimits allow); empty when it is. The settling stops
  /// at the first such step: a crumpled body has no static sag to press.
  std::string implausible;
  Eigen::Matrix3Xd positions;  ///< the body where it came to rest (3 x #V, m)
};

/// Runs `model` with the parameter block `params` on the scene from rest until it is at rest,
/// its fixed region held and gravity on (grasp, instrument, gravity's off time and the initial
/// velocity ignored), judged by RunMonitor like every run. Damping only shortens this: a static
/// equilibrium does not depend on it. Throws InputError when the scene's fixed region selects
/// no vertex (a free body has no static sag).
StaticSag static_sag(const scenes::Scene& scene,
                     const TetMesh& mesh,
                     const std::string& model,
                     const nlohmann::json& params,
                     const StaticSagOptions& options = {});

/// `params` with the model's settling damping (ModelInfo::settling_damping) where it sets none
/// or zero: for the runs that only need the equilibrium.
nlohmann::json with_settling_damping(const std::string& model, nlohmann::json params);

/// The press: the scene's instrument, turned so its tip (its mesh's -z end, as the shipped
/// probe's) points along gravity, starts `approach` above the settled body's press vertex and
/// moves down along gravity at `speed`, to `overshoot` past the deepest depth. The press vertex
/// is the rest surface's highest vertex (against gravity) within a tenth of the body's diagonal
/// of the vertical through the free vertices' centre of mass: the middle of what hangs, so the
/// same on every scene with this mesh, fixed region and gravity. First contact is the tip
/// reaching the press vertex's settled height: each model is pressed from its own sag.
struct PressSettings {
  std::vector<double> depths{0.005, 0.01, 0.02};  ///< m past first contact: where force is read
  double approach = 0.01;                         ///< m
  double speed = 0.04;                            ///< m/s (the shipped press scene's pace)
  double overshoot = 0.0025;                      ///< m
  /// When the sag counts as static. 20 s: a candidate far too soft (shape matching at a small
  /// alpha creeps for a minute) is measured still creeping, which only makes it look worse.
  StaticSagOptions settling{2e-4, 20.0};
};

struct TissueResponse {
  StaticSag sag;
  /// N: the force the tissue exerts on the tool at each depth (NaN where the press did not get
  /// there: it blew up).
  std::vector<double> forces;
  bool press_stable = true;
  /// The sag's StaticSag::implausible, or the first step of the press that left a tissue's
  /// shape, or "still moving after N s" when the sag did not settle (a creeping or crumpling
  /// body has no static sag); empty for a tissue's response.
  std::string implausible;
  int press_vertex = -1;
  double seconds = 0.0;  ///< wall-clock time of both runs
};

/// The press vertex (see PressSettings). Throws InputError when the scene has no fixed region.
int press_vertex(const scenes::Scene& scene, const TetMesh& mesh);

/// Both targets for `model` with `params` (settling damping added where the block has none):
/// the static sag, then the press on the same body from that rest state.
/// Throws InputError when the scene has no instrument or no fixed region.
TissueResponse tissue_response(const scenes::Scene& scene,
                               const SceneMesh& mesh,
                               const std::string& model,
                               const nlohmann::json& params,
                               const PressSettings& settings = {});

nlohmann::json to_json(const TissueResponse& response);
/// The targets back from to_json (the positions are not kept).
TissueResponse tissue_response_from_json(const nlohmann::json& json);

}  // namespace softbench::harness
