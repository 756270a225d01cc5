// SPDX-License-Identifier: MIT
// How far a run is from the converged reference: the reference's shapes at fixed times, the
// run's shapes at the same times, and the errors between them. The reference itself is run and
// cached by reference.h.
#pragma once

#include "scenes/scene.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <optional>
#include <vector>

namespace softbench::harness {

/// The body at one of the compared times.
struct Snapshot {
  double time = 0.0;           ///< s, the requested time
  Eigen::Matrix3Xd positions;  ///< 3 x #V, m
  double volume = 0.0;         ///< m^3
};

struct ReferenceRun {
  nlohmann::json settings;                  ///< what was run (scene, model, dt), for the record
  std::vector<double> times;                ///< s
  std::vector<Eigen::Matrix3Xd> positions;  ///< 3 x #V at each time
  std::vector<double> volumes;              ///< m^3 at each time
  double peak_tool_force = 0.0;             ///< N
};

/// How far a run is from the converged reference, over the compared times.
struct Accuracy {
  double rms_error = 0.0;     ///< mean over times of RMS |x - x_ref| / RMS |x_ref - x_rest|
  double max_error = 0.0;     ///< largest over times of max |x - x_ref| / max |x_ref - x_rest|
  double volume_error = 0.0;  ///< largest over times of |V - V_ref| / V_ref
  std::optional<double> peak_force_error;  ///< |F - F_ref| / F_ref of the peak tool force
  /// mean over times of RMS |x - x_ref| / the rest bounding-box diagonal: the error as a share
  /// of the body's size, comparable across scenes however far the reference moved.
  double diagonal_error = 0.0;
};

/// The compared times for `scene`: `count` evenly spaced in (0, duration].
std::vector<double> comparison_times(const scenes::Scene& scene, int count);
/// The instants a scene is drawn at (the thesis's figures): when its instrument or grasp lets
/// go (the deepest press, the end of the pull), if within the scene, and its end (the
/// recovery). Increasing.
std::vector<double> picture_times(const scenes::Scene& scene);

/// A run's `snapshots` (at the reference's times) and peak tool force against `reference`;
/// `rest` is the rest shape. A run that blew up before a time is infinitely wrong there.
Accuracy accuracy_against(const std::vector<Snapshot>& snapshots,
                          double peak_tool_force,
                          const ReferenceRun& reference,
                          const Eigen::Matrix3Xd& rest);

}  // namespace softbench::harness
