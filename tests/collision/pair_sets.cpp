// SPDX-License-Identifier: MIT
#include "tests/collision/pair_sets.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <random>
#include <sstream>
#include <string>
#include <utility>

namespace softbench::collision::test {
namespace {

using Vec3 = Eigen::Vector3d;
using Contact = TriTriContact;

const std::array<Vec3, 3> kA = {Vec3(0.5, 1.5, 0.0), Vec3(0.0, 0.0, 0.0), Vec3(2.0, 0.0, 0.0)};

/// The designed pairs: a line "<figure case> <expected contact> <label>", then B's vertices
/// ("B x y z, x y z, x y z") and, when A is not kA, A's before them. Coordinates are exact
/// doubles as written (shortest round-trip decimals).
constexpr const char* kDesignedPairs = R"(
a disjoint (a) rejected on V: B above A in y
  B 0 2 0, 1 2 0, 0 3 0
a disjoint (a) rejected on W: B right of A in x
  B 3 0 0, 4 0 0, 3 1 0
a disjoint (a) passes V and W, disjoint near P2
  B 2 1 0, 3 1 0, 2 2 0
a coplanar (a) coplanar overlap, edges cross
  B 1 0.5 0, 3 0.5 0, 1 2 0
a coplanar (a) coplanar containment: B inside A
  B 0.5 0.2 0, 1 0.2 0, 0.6 0.6 0
a coplanar (a) coplanar containment: A inside B (figure 4.17)
  B -1 -1 0, 5 -1 0, -1 5 0
a coplanar (a) coplanar shared vertex P2
  B 2 0 0, 3 0 0, 3 1 0
a coplanar (a) coplanar shared edge P1P2 (mesh neighbours)
  B 0 0 0, 2 0 0, 1 -1 0
a coplanar (a) coplanar vertex on edge P1P2
  B 1 0 0, 1.5 -1 0, 0.5 -1 0
a coplanar (a) identical
  B 0.5 1.5 0, 0 0 0, 2 0 0
a coplanar (a) identical, reversed orientation
  B 0.5 1.5 0, 2 0 0, 0 0 0
a disjoint (a) coplanar gap 1e-12 below P1P2
  B 1 -1e-12 0, 1.5 -1 0, 0.5 -1 0
b disjoint (b) B above H
  B 0 0 1, 2 0 2, 0 2 1.5
b disjoint (b) B below H
  B 0 0 -1, 2 0 -2, 0 2 -1.5
b disjoint (b) parallel copy 1e-9 above
  B 0.5 1.5 1e-09, 0 0 1e-09, 2 0 1e-09
b disjoint (b) vertex 1e-15 above the face
  B 1 0.5 1e-15, 1 0.5 1, 0 0 1
c segment (c) vertex on face: point contact
  B 1 0.5 0, 1 0.5 1, 0 0 1
c disjoint (c) rejected on V: Q0 beyond P0's height
  B 1 2 0, 1 2 1, 0 0 1
c disjoint (c) rejected on W: Q0 right of P2
  B 3 0.5 0, 3 0.5 1, 0 0 1
c disjoint (c) passes V and W, Q0 outside A
  B 1.8 1 0, 1.8 1 -1, 0 0 -1
c segment (c) shared vertex P0 only, 3D
  B 0.5 1.5 0, 1.5 1.5 1, 0.5 2.5 1
c segment (c) vertex on edge P1P2
  B 1 0 0, 1 -1 1, 2 -1 1
d segment (d) edge in plane, inside A
  B 0.5 0.3 0, 1 0.3 0, 0.7 0.3 1
d segment (d) edge in plane, crossing A's boundary
  B 1 0.5 0, 3 0.5 0, 2 0.5 -1
d disjoint (d) rejected on V
  B 0 2 0, 1 2 0, 0.5 2 1
d disjoint (d) rejected on W
  B 3 0.2 0, 4 1 0, 3.5 1 1
d segment (d) shared edge P1P2, dihedral (mesh neighbours)
  B 0 0 0, 2 0 0, 1 -1 1
d disjoint (d) passes V and W, outside near P2
  B 1.5 1 0, 2 1.5 0, 1.7 1.2 1
d segment (d) in-plane edge touching P0 only
  B 0 1.5 0, 1 1.5 0, 0.5 2 1
e segment (e) L_B inside A
  B 1 0.5 0, 1 0.2 1, 1 0.2 -1
e disjoint (e) rejected on V
  B 1 2 0, 1 3 1, 1 3 -1
e disjoint (e) rejected on W
  B 3 0.5 0, 4 0.5 1, 4 0.5 -1
e segment (e) Q0 on edge P1P2, L_B outside
  B 1 0 0, 1 -1 1, 1 -1 -1
e disjoint (e) passes V and W, misses A
  B 1.9 0.9 0, 1.6 1.2 1, 1.6 1.2 -1
f segment (f) B pierces A
  B 1 0.5 1, 0.5 0.3 -1, 1.5 0.3 -1
f disjoint (f) rejected on V
  B 1 3.5 1, 0.5 3.3 -1, 1.5 3.3 -1
f disjoint (f) rejected on W
  B 6 0.5 1, 5.5 0.3 -1, 6.5 0.3 -1
f disjoint (f) passes V and W, misses near P2
  B 1.9 1 1, 1.7 0.8 -1, 2.1 0.8 -1
f segment (f) edge crosses edge P1P2 exactly: edge contact point
  B 1 -0.5 1, 1 0.5 -1, 1 -2 -1
f disjoint (f) edge misses edge P1P2 by 1e-12
  B 1 -0.500000000001 1, 1 0.499999999999 -1, 1 -2 -1
f segment (f) B's face through P0 only (vertex on face)
  B 0.5 1.5 1, -0.5 1.5 -1, 1.5 1.5 -1
f segment (f) A's edge P1P2 in B's plane (edge in plane)
  B 1 0 1, 0 0 -1, 2.5 0 -1
f segment (f) near-coplanar tilt 1e-10, crossing
  B 1 0.6 -1e-10, 0.5 0.5 1e-10, 1.5 0.5 1e-10
d segment (f) large coordinates 1e4, shared edge dihedral
  A 10000 10000 10000, 10001 10000 10000, 10000 10001 10000
  B 10001 10000 10000, 10000 10000 10000, 10000.5 9999 10001
b disjoint (f) small triangles (1e-3) 1e-5 apart
  A 0 0 0, 0.001 0 0, 0 0.001 0
  B 0 0 1e-05, 0.001 0 1e-05, 0 0.001 2e-05
a coplanar (a) tilted plane x+y+z=1, touching at a vertex
  A 1 0 0, 0 1 0, 0 0 1
  B 0 0 1, -1 0 2, 0 -1 2
degenerate segment degenerate B: segment piercing A
  B 1 0.5 -1, 1 0.5 1, 1 0.5 0.25
degenerate disjoint degenerate B: segment missing A
  B 3 3 -1, 3 3 1, 3 3 0
degenerate coplanar degenerate B: segment in A's plane crossing A
  B 1 0.5 0, 3 0.5 0, 2 0.5 0
degenerate disjoint degenerate B: segment in A's plane outside A
  B 1 2 0, 3 2 0, 2 2 0
degenerate segment degenerate B: point inside A
  B 1 0.5 0, 1 0.5 0, 1 0.5 0
degenerate disjoint degenerate B: point 1e-9 above A
  B 1 0.5 1e-09, 1 0.5 1e-09, 1 0.5 1e-09
degenerate segment degenerate A (segment) piercing B
  A 1 0.5 -1, 1 0.5 1, 1 0.5 0.5
  B 0.5 1.5 0, 0 0 0, 2 0 0
degenerate segment degenerate both: segments crossing
  A 0 0 0, 2 0 0, 1 0 0
  B 1 -1 0, 1 1 0, 1 0.5 0
degenerate disjoint degenerate both: parallel segments
  A 0 0 0, 2 0 0, 1 0 0
  B 0 1 0, 2 1 0, 1 1 0
degenerate segment degenerate both: collinear overlapping segments
  A 0 0 0, 2 2 2, 1 1 1
  B 1.5 1.5 1.5, 3 3 3, 4 4 4
)";

class Sampler {
 public:
  explicit Sampler(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(engine_);
  }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(engine_); }
  Vec3 box(double half) {
    return {uniform(-half, half), uniform(-half, half), uniform(-half, half)};
  }
  Vec3 grid(int lo, int hi) {
    return {static_cast<double>(integer(lo, hi)), static_cast<double>(integer(lo, hi)),
            static_cast<double>(integer(lo, hi))};
  }

  /// The random-pair recipe (see random_pairs in pair_sets.h).
  TriPair recipe_pair() {
    TriPair pair;
    const Vec3 centre(uniform(0.0, 1.0), uniform(0.0, 1.0), uniform(0.0, 1.0));
    for (auto& v : pair.a) {
      v = centre + box(0.1);
    }
    const Vec3 centroid = (pair.a[0] + pair.a[1] + pair.a[2]) / 3.0;
    const Vec3 centre_b = centroid + box(0.05);
    for (auto& v : pair.b) {
      v = (centre_b + box(0.1)).cwiseMax(0.0).cwiseMin(1.0);
    }
    return pair;
  }

  /// A proper integer triangle in [lo, hi]^3.
  std::array<Vec3, 3> grid_triangle(int lo, int hi) {
    while (true) {
      std::array<Vec3, 3> t = {grid(lo, hi), grid(lo, hi), grid(lo, hi)};
      if ((t[1] - t[0]).cross(t[2] - t[0]).squaredNorm() > 0.0) {
        return t;
      }
    }
  }

 private:
  std::mt19937_64 engine_;
};

/// x moved onto the plane of t in floating point: within rounding of it, usually not on it.
Vec3 snap_to_plane(const Vec3& x, const std::array<Vec3, 3>& t) {
  const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
  return x - n.dot(x - t[0]) * n;
}

}  // namespace

std::vector<DesignedPair> designed_pairs() {
  std::vector<DesignedPair> pairs;
  std::istringstream lines{std::string(kDesignedPairs)};
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty()) {
      continue;
    }
    std::istringstream fields(line);
    std::string key;
    fields >> key;
    if (key == "A" || key == "B") {
      std::array<Vec3, 3>& t = key == "A" ? pairs.back().pair.a : pairs.back().pair.b;
      for (Vec3& v : t) {
        char comma = 0;
        fields >> v.x() >> v.y() >> v.z();
        fields >> comma;  // "," between vertices
      }
      continue;
    }
    DesignedPair d;
    d.figure_case = key;
    std::string expected;
    fields >> expected;
    d.expected = expected == "disjoint"  ? Contact::kDisjoint
                 : expected == "segment" ? Contact::kSegment
                                         : Contact::kCoplanar;
    std::getline(fields >> std::ws, d.label);
    d.pair.a = kA;
    pairs.push_back(std::move(d));
  }
  return pairs;
}

std::vector<TriPair> random_pairs(std::size_t count, std::uint64_t seed) {
  Sampler sampler(seed);
  std::vector<TriPair> pairs(count);
  for (auto& pair : pairs) {
    pair = sampler.recipe_pair();
  }
  return pairs;
}

std::vector<PairFamily> near_degenerate_families(std::size_t count, std::uint64_t seed) {
  Sampler sampler(seed);
  std::vector<PairFamily> families;
  auto family = [&](std::string name, auto&& make) {
    PairFamily f{std::move(name), {}};
    f.pairs.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
      f.pairs.push_back(make());
    }
    families.push_back(std::move(f));
  };
  family("vertex snapped onto the other plane", [&] {
    TriPair pair = sampler.recipe_pair();
    pair.b[0] = snap_to_plane(pair.b[0], pair.a);
    return pair;
  });
  family("edge snapped into the other plane", [&] {
    TriPair pair = sampler.recipe_pair();
    pair.b[0] = snap_to_plane(pair.b[0], pair.a);
    pair.b[1] = snap_to_plane(pair.b[1], pair.a);
    return pair;
  });
  family("edges crossing exactly (integer grid)", [&] {
    TriPair pair;
    pair.a = sampler.grid_triangle(-8, 8);
    const int edge = sampler.integer(0, 2);
    const Vec3 cross = 0.5 * (pair.a[edge] + pair.a[(edge + 1) % 3]);  // exact
    Vec3 d = sampler.grid(-4, 4);
    while (d.squaredNorm() == 0.0) {
      d = sampler.grid(-4, 4);
    }
    pair.b = {cross + 0.5 * d, cross - 0.5 * d, sampler.grid(-8, 8)};  // exact halves
    return pair;
  });
  family("mesh neighbours sharing an edge", [&] {
    TriPair pair = sampler.recipe_pair();
    pair.b[0] = pair.a[1];
    pair.b[1] = pair.a[0];
    return pair;
  });
  family("mesh neighbours sharing a vertex", [&] {
    TriPair pair = sampler.recipe_pair();
    pair.b[0] = pair.a[sampler.integer(0, 2)];
    return pair;
  });
  family("exactly coplanar (x+y+z=0, integer)", [&] {
    auto on_plane = [&] {
      const double x = sampler.integer(-4, 4);
      const double y = sampler.integer(-4, 4);
      return Vec3(x, y, -x - y);
    };
    return TriPair{{on_plane(), on_plane(), on_plane()}, {on_plane(), on_plane(), on_plane()}};
  });
  family("integer grid [0,3]^3", [&] {
    return TriPair{{sampler.grid(0, 3), sampler.grid(0, 3), sampler.grid(0, 3)},
                   {sampler.grid(0, 3), sampler.grid(0, 3), sampler.grid(0, 3)}};
  });
  family("near-parallel planes (offset 1e-9 * U)", [&] {
    TriPair pair = sampler.recipe_pair();
    const Vec3 n = (pair.a[1] - pair.a[0]).cross(pair.a[2] - pair.a[0]).normalized();
    for (int i = 0; i < 3; ++i) {
      pair.b[i] = snap_to_plane(pair.b[i], pair.a) + sampler.uniform(-1e-9, 1e-9) * n;
    }
    return pair;
  });
  return families;
}

}  // namespace softbench::collision::test
