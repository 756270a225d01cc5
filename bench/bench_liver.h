// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/soft_body.h"

#include <string>
#include <vector>

// The scene-like set-up every model benchmark shares, so all of them time the same work.
namespace softbench::bench {

/// A shipped liver ("liver.msh", "liver_x4.msh", "liver_x16.msh"), read and validated once per
/// process on first use (not at registration, so running one benchmark loads one mesh).
const TetMesh& shipped_liver(const std::string& name);

/// Exact pins on the vertices in the lowest 10% of the x extent: the benchmarks' fixed region.
std::vector<PositionConstraint> pin_lowest_tenth_in_x(const TetMesh& mesh);

}  // namespace softbench::bench
