// SPDX-License-Identifier: MIT
#pragma once

#include "harness/compare/comparison.h"
#include "scenes/scene.h"

#include <filesystem>
#include <ostream>
#include <vector>

namespace softbench::harness {

/// Draws each scene's runs at their picture times (ModelRun::pictures; harness/run/accuracy.h's
/// picture_times) into `out_dir`, one PNG per scene and table (pictures_<scene>_A.png, and _B.png
/// for the matched table), and records them in comparison.pictures so that compare.md shows
/// them. `scenes` are the scenes as run, in comparison.scenes' order. Does nothing in a build
/// without the renderer; a machine whose EGL cannot draw is told on `progress` and the report
/// goes without pictures.
void draw_comparison_pictures(const std::filesystem::path& out_dir,
                              const std::vector<scenes::Scene>& scenes,
                              Comparison& comparison,
                              std::ostream& progress);

/// compare.md's pictures section (empty without pictures).
void pictures_markdown(std::ostream& out, const Comparison& comparison);

}  // namespace softbench::harness
