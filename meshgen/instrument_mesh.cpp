// SPDX-License-Identifier: MIT
#include "meshgen/instrument_mesh.h"

#include "geometry/input_error.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace softbench::meshgen {
namespace {

struct ProfilePoint {
  double radius;  // m from the axis
  double height;  // m along +z
};

// The profile from the tip pole to the proximal pole, `rings` points strictly between them.
// A third of the rings round the tip (a hemisphere), a third shape the jaw section (slightly
// wider than the shaft, like a closed grasper's jaws), the rest run along the shaft, whose end
// is rounded off so the proximal pole is not a flat fan of slivers.
std::vector<ProfilePoint> probe_profile(const InstrumentOptions& options) {
  const double r = options.shaft_radius;
  const int tip_rings = std::max(2, options.rings / 3);
  const int jaw_rings = std::max(2, options.rings / 3);
  const int end_rings = std::max(2, options.rings - tip_rings - jaw_rings);
  const double jaw_length = 8.0 * r;
  std::vector<ProfilePoint> profile;
  for (int i = 1; i <= tip_rings; ++i) {
    const double angle = 0.5 * std::numbers::pi * i / tip_rings;
    profile.push_back({r * std::sin(angle), r * (1.0 - std::cos(angle))});
  }
  for (int i = 1; i <= jaw_rings; ++i) {
    const double s = static_cast<double>(i) / jaw_rings;
    // A bulge of 20% over the jaw section, back to the shaft radius at its end.
    profile.push_back({r * (1.0 + 0.2 * std::sin(std::numbers::pi * s)), r + jaw_length * s});
  }
  const double shaft_start = r + jaw_length;
  const double shaft_end = options.length - r;
  for (int i = 1; i <= end_rings; ++i) {
    const double s = static_cast<double>(i) / end_rings;
    // Most rings space the shaft evenly; the last quarter-circle closes it.
    if (i < end_rings) {
      profile.push_back({r, shaft_start + (shaft_end - shaft_start) * s});
    } else {
      const double angle = 0.25 * std::numbers::pi;
      profile.push_back({r * std::cos(angle), shaft_end + r * std::sin(angle)});
    }
  }
  return profile;
}

}  // namespace

TriMesh make_probe_instrument(const InstrumentOptions& options) {
  if (options.segments < 3 || options.rings < 6 || options.shaft_radius <= 0.0
      || options.length <= 12.0 * options.shaft_radius) {
    throw InputError("instrument: need segments >= 3, rings >= 6 and a length over 12 shaft radii");
  }
  const std::vector<ProfilePoint> profile = probe_profile(options);
  const int rings = static_cast<int>(profile.size());
  const int segments = options.segments;
  TriMesh mesh;
  mesh.vertices.resize(3, rings * segments + 2);
  const int tip_pole = 0;
  const int end_pole = rings * segments + 1;
  const auto ring_vertex = [segments](int ring, int segment) {
    return 1 + ring * segments + (segment % segments);
  };
  mesh.vertices.col(tip_pole) << 0.0, 0.0, 0.0;
  mesh.vertices.col(end_pole) << 0.0, 0.0, options.length;
  for (int ring = 0; ring < rings; ++ring) {
    for (int segment = 0; segment < segments; ++segment) {
      const double angle = 2.0 * std::numbers::pi * segment / segments;
      const ProfilePoint& p = profile[static_cast<std::size_t>(ring)];
      mesh.vertices.col(ring_vertex(ring, segment)) << p.radius * std::cos(angle),
          p.radius * std::sin(angle), p.height;
    }
  }

  // Counter-clockwise seen from outside: with z growing from ring to ring and the angle growing
  // counter-clockwise about +z, (lower, upper, next-upper) faces outward.
  mesh.triangles.resize(3, 2 * segments * rings);
  int t = 0;
  for (int segment = 0; segment < segments; ++segment) {
    mesh.triangles.col(t++) << tip_pole, ring_vertex(0, segment + 1), ring_vertex(0, segment);
  }
  for (int ring = 0; ring + 1 < rings; ++ring) {
    for (int segment = 0; segment < segments; ++segment) {
      const int a = ring_vertex(ring, segment);
      const int b = ring_vertex(ring, segment + 1);
      const int c = ring_vertex(ring + 1, segment);
      const int d = ring_vertex(ring + 1, segment + 1);
      mesh.triangles.col(t++) << a, b, d;
      mesh.triangles.col(t++) << a, d, c;
    }
  }
  for (int segment = 0; segment < segments; ++segment) {
    mesh.triangles.col(t++) << end_pole, ring_vertex(rings - 1, segment),
        ring_vertex(rings - 1, segment + 1);
  }
  return mesh;
}

}  // namespace softbench::meshgen
