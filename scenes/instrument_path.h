// SPDX-License-Identifier: MIT
#pragma once

#include "scenes/scene.h"

#include <Eigen/Geometry>

namespace softbench::scenes {

/// The instrument's pose (its mesh frame -> world) at `time`: linear in position and slerp in
/// orientation between keyframes, held before the first and after the last.
Eigen::Isometry3d instrument_pose(const Instrument& instrument, double time);

}  // namespace softbench::scenes
