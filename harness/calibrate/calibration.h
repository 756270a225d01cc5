// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>

namespace softbench::harness {

// Calibration of a stiffness that has no physical unit (bullet_softbody's kLST: its effect
// depends on dt, iterations and mesh) against a physical reference: the static sag of the scene's
// body under the scene's gravity with its fixed region held (grasp, instrument, gravity's off
// time and the initial velocity ignored), at the scene's dt. A free body (no fixed region) has
// no static sag: it is refused with an InputError naming /fixed.

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
};

/// Runs `model` with the parameter block `params` on the scene from rest until it is at rest,
/// judged by RunMonitor like every run. Damping only shortens this: a static equilibrium does
/// not depend on it. Throws InputError when the scene's fixed region selects no vertex.
StaticSag static_sag(const scenes::Scene& scene,
                     const TetMesh& mesh,
                     const std::string& model,
                     const nlohmann::json& params,
                     const StaticSagOptions& options = {});

struct StiffnessCalibration {
  std::string against;         ///< reference model
  double reference_sag = 0.0;  ///< m
  double sag = 0.0;            ///< m, bullet_softbody's with the fitted parameters
  nlohmann::json params;       ///< the block to paste into the scene, "calibrated" included
  int evaluations = 0;         ///< bullet_softbody runs it took
};

/// Fits bullet_softbody's stiffness (bisection on log kLST; position_iterations doubled first if
/// even kLST = 1 is too soft) until its static sag is within `tolerance` (relative) of the
/// reference's: corotational_fem when registered, else mass_spring with springs from Young's
/// modulus as a stand-in. Starts from the scene's bullet_softbody block. Throws InputError when
/// no stiffness in range matches.
StiffnessCalibration calibrate_bullet_softbody(const scenes::Scene& scene,
                                               double tolerance,
                                               std::ostream* progress);

/// "1.234 cm": a length in centimetres with three decimals, for the calibration's messages.
std::string format_cm(double metres);

/// The model calibrate_bullet_softbody fits.
inline constexpr const char* kCalibratedModel = "bullet_softbody";

}  // namespace softbench::harness
