// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tri_mesh.h"

namespace softbench::meshgen {

/// A laparoscopic probe as a closed surface of revolution about +z: a rounded tip at the origin,
/// a short tapered jaw section, the 5 mm shaft and a closed proximal end. The thesis's instrument
/// has 628 vertices and 1248 triangles; the defaults give 626 and 1248 (24 segments x 26 rings +
/// 2 poles), a closed genus-0 manifold (the thesis's counts cannot be: V - E + F != 2).
struct InstrumentOptions {
  double shaft_radius = 0.0025;  ///< m (a 5 mm instrument)
  double length = 0.16;          ///< m from tip to proximal end
  int segments = 24;             ///< around the axis
  int rings = 26;                ///< between the two poles
};

TriMesh make_probe_instrument(const InstrumentOptions& options = {});

}  // namespace softbench::meshgen
