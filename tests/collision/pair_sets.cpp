// SPDX-License-Identifier: MIT
#include "tests/collision/pair_sets.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <random>
#include <utility>

namespace softbench::collision::test {
namespace {

using Vec3 = Eigen::Vector3d;
using Contact = TriTriContact;

const std::array<Vec3, 3> kA = {Vec3(0.5, 1.5, 0.0), Vec3(0.0, 0.0, 0.0), Vec3(2.0, 0.0, 0.0)};

DesignedPair against_a(std::string label,
                       std::string figure_case,
                       const Vec3& q0,
                       const Vec3& q1,
                       const Vec3& q2,
                       Contact expected) {
  return {std::move(label), std::move(figure_case), TriPair{kA, {q0, q1, q2}}, expected};
}

DesignedPair general(std::string label,
                     std::string figure_case,
                     std::array<Vec3, 3> a,
                     std::array<Vec3, 3> b,
                     Contact expected) {
  return {std::move(label), std::move(figure_case), TriPair{a, b}, expected};
}

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

  /// The notes' recipe (section 2).
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
  using V = Vec3;
  std::vector<DesignedPair> p;
  // (a) B in H: V and W overlap of the projections, then coplanar triangles (figure 4.17).
  p.push_back(against_a("(a) rejected on V: B above A in y", "a", V(0, 2, 0), V(1, 2, 0),
                        V(0, 3, 0), Contact::kDisjoint));
  p.push_back(against_a("(a) rejected on W: B right of A in x", "a", V(3, 0, 0), V(4, 0, 0),
                        V(3, 1, 0), Contact::kDisjoint));
  p.push_back(against_a("(a) passes V and W, disjoint near P2", "a", V(2, 1, 0), V(3, 1, 0),
                        V(2, 2, 0), Contact::kDisjoint));
  p.push_back(against_a("(a) coplanar overlap, edges cross", "a", V(1, 0.5, 0), V(3, 0.5, 0),
                        V(1, 2, 0), Contact::kCoplanar));
  p.push_back(against_a("(a) coplanar containment: B inside A", "a", V(0.5, 0.2, 0), V(1.0, 0.2, 0),
                        V(0.6, 0.6, 0), Contact::kCoplanar));
  p.push_back(against_a("(a) coplanar containment: A inside B (figure 4.17)", "a", V(-1, -1, 0),
                        V(5, -1, 0), V(-1, 5, 0), Contact::kCoplanar));
  p.push_back(against_a("(a) coplanar shared vertex P2", "a", V(2, 0, 0), V(3, 0, 0), V(3, 1, 0),
                        Contact::kCoplanar));
  p.push_back(against_a("(a) coplanar shared edge P1P2 (mesh neighbours)", "a", V(0, 0, 0),
                        V(2, 0, 0), V(1, -1, 0), Contact::kCoplanar));
  p.push_back(against_a("(a) coplanar vertex on edge P1P2", "a", V(1, 0, 0), V(1.5, -1, 0),
                        V(0.5, -1, 0), Contact::kCoplanar));
  p.push_back(against_a("(a) identical", "a", kA[0], kA[1], kA[2], Contact::kCoplanar));
  p.push_back(against_a("(a) identical, reversed orientation", "a", kA[0], kA[2], kA[1],
                        Contact::kCoplanar));
  p.push_back(against_a("(a) coplanar gap 1e-12 below P1P2", "a", V(1, -1e-12, 0), V(1.5, -1, 0),
                        V(0.5, -1, 0), Contact::kDisjoint));
  // (b) B strictly on one side of H.
  p.push_back(
      against_a("(b) B above H", "b", V(0, 0, 1), V(2, 0, 2), V(0, 2, 1.5), Contact::kDisjoint));
  p.push_back(
      against_a("(b) B below H", "b", V(0, 0, -1), V(2, 0, -2), V(0, 2, -1.5), Contact::kDisjoint));
  p.push_back(against_a("(b) parallel copy 1e-9 above", "b", kA[0] + V(0, 0, 1e-9),
                        kA[1] + V(0, 0, 1e-9), kA[2] + V(0, 0, 1e-9), Contact::kDisjoint));
  p.push_back(against_a("(b) vertex 1e-15 above the face", "b", V(1, 0.5, 1e-15), V(1, 0.5, 1),
                        V(0, 0, 1), Contact::kDisjoint));
  // (c) Q0 on H, Q1 and Q2 on one side: Q_L = Q_R = Q0, point in triangle (figure 4.18).
  p.push_back(against_a("(c) vertex on face: point contact", "c", V(1, 0.5, 0), V(1, 0.5, 1),
                        V(0, 0, 1), Contact::kSegment));
  p.push_back(against_a("(c) rejected on V: Q0 beyond P0's height", "c", V(1, 2, 0), V(1, 2, 1),
                        V(0, 0, 1), Contact::kDisjoint));
  p.push_back(against_a("(c) rejected on W: Q0 right of P2", "c", V(3, 0.5, 0), V(3, 0.5, 1),
                        V(0, 0, 1), Contact::kDisjoint));
  p.push_back(against_a("(c) passes V and W, Q0 outside A", "c", V(1.8, 1.0, 0), V(1.8, 1, -1),
                        V(0, 0, -1), Contact::kDisjoint));
  p.push_back(against_a("(c) shared vertex P0 only, 3D", "c", V(0.5, 1.5, 0), V(1.5, 1.5, 1),
                        V(0.5, 2.5, 1), Contact::kSegment));
  p.push_back(against_a("(c) vertex on edge P1P2", "c", V(1, 0, 0), V(1, -1, 1), V(2, -1, 1),
                        Contact::kSegment));
  // (d) Q0, Q1 on H: L_B = Q0Q1, segment against A in H (figure 4.16).
  p.push_back(against_a("(d) edge in plane, inside A", "d", V(0.5, 0.3, 0), V(1, 0.3, 0),
                        V(0.7, 0.3, 1), Contact::kSegment));
  p.push_back(against_a("(d) edge in plane, crossing A's boundary", "d", V(1, 0.5, 0), V(3, 0.5, 0),
                        V(2, 0.5, -1), Contact::kSegment));
  p.push_back(against_a("(d) rejected on V", "d", V(0, 2, 0), V(1, 2, 0), V(0.5, 2, 1),
                        Contact::kDisjoint));
  p.push_back(against_a("(d) rejected on W", "d", V(3, 0.2, 0), V(4, 1, 0), V(3.5, 1, 1),
                        Contact::kDisjoint));
  p.push_back(against_a("(d) shared edge P1P2, dihedral (mesh neighbours)", "d", V(0, 0, 0),
                        V(2, 0, 0), V(1, -1, 1), Contact::kSegment));
  p.push_back(against_a("(d) passes V and W, outside near P2", "d", V(1.5, 1.0, 0), V(2.0, 1.5, 0),
                        V(1.7, 1.2, 1), Contact::kDisjoint));
  p.push_back(against_a("(d) in-plane edge touching P0 only", "d", V(0, 1.5, 0), V(1, 1.5, 0),
                        V(0.5, 2, 1), Contact::kSegment));
  // (e) Q0 on H, Q1 and Q2 on opposite sides: Q_L = Q0, Q_R on Q1Q2.
  p.push_back(against_a("(e) L_B inside A", "e", V(1, 0.5, 0), V(1, 0.2, 1), V(1, 0.2, -1),
                        Contact::kSegment));
  p.push_back(
      against_a("(e) rejected on V", "e", V(1, 2, 0), V(1, 3, 1), V(1, 3, -1), Contact::kDisjoint));
  p.push_back(against_a("(e) rejected on W", "e", V(3, 0.5, 0), V(4, 0.5, 1), V(4, 0.5, -1),
                        Contact::kDisjoint));
  p.push_back(against_a("(e) Q0 on edge P1P2, L_B outside", "e", V(1, 0, 0), V(1, -1, 1),
                        V(1, -1, -1), Contact::kSegment));
  p.push_back(against_a("(e) passes V and W, misses A", "e", V(1.9, 0.9, 0), V(1.6, 1.2, 1),
                        V(1.6, 1.2, -1), Contact::kDisjoint));
  // (f) Q0 alone on its side: Q_L on Q0Q1, Q_R on Q0Q2 by t = |z1| / (|z1| + |z0|).
  p.push_back(against_a("(f) B pierces A", "f", V(1, 0.5, 1), V(0.5, 0.3, -1), V(1.5, 0.3, -1),
                        Contact::kSegment));
  p.push_back(against_a("(f) rejected on V", "f", V(1, 3.5, 1), V(0.5, 3.3, -1), V(1.5, 3.3, -1),
                        Contact::kDisjoint));
  p.push_back(against_a("(f) rejected on W", "f", V(6, 0.5, 1), V(5.5, 0.3, -1), V(6.5, 0.3, -1),
                        Contact::kDisjoint));
  p.push_back(against_a("(f) passes V and W, misses near P2", "f", V(1.9, 1.0, 1), V(1.7, 0.8, -1),
                        V(2.1, 0.8, -1), Contact::kDisjoint));
  p.push_back(against_a("(f) edge crosses edge P1P2 exactly: edge contact point", "f",
                        V(1, -0.5, 1), V(1, 0.5, -1), V(1, -2, -1), Contact::kSegment));
  p.push_back(against_a("(f) edge misses edge P1P2 by 1e-12", "f", V(1, -0.5 - 1e-12, 1),
                        V(1, 0.5 - 1e-12, -1), V(1, -2, -1), Contact::kDisjoint));
  p.push_back(against_a("(f) B's face through P0 only (vertex on face)", "f", V(0.5, 1.5, 1),
                        V(-0.5, 1.5, -1), V(1.5, 1.5, -1), Contact::kSegment));
  p.push_back(against_a("(f) A's edge P1P2 in B's plane (edge in plane)", "f", V(1, 0, 1),
                        V(0, 0, -1), V(2.5, 0, -1), Contact::kSegment));
  p.push_back(against_a("(f) near-coplanar tilt 1e-10, crossing", "f", V(1, 0.6, -1e-10),
                        V(0.5, 0.5, 1e-10), V(1.5, 0.5, 1e-10), Contact::kSegment));
  p.push_back(general("(f) large coordinates 1e4, shared edge dihedral", "d",
                      {V(1e4, 1e4, 1e4), V(1e4 + 1, 1e4, 1e4), V(1e4, 1e4 + 1, 1e4)},
                      {V(1e4 + 1, 1e4, 1e4), V(1e4, 1e4, 1e4), V(1e4 + 0.5, 1e4 - 1, 1e4 + 1)},
                      Contact::kSegment));
  p.push_back(general("(f) small triangles (1e-3) 1e-5 apart", "b",
                      {V(0, 0, 0), V(1e-3, 0, 0), V(0, 1e-3, 0)},
                      {V(0, 0, 1e-5), V(1e-3, 0, 1e-5), V(0, 1e-3, 2e-5)}, Contact::kDisjoint));
  p.push_back(general("(a) tilted plane x+y+z=1, touching at a vertex", "a",
                      {V(1, 0, 0), V(0, 1, 0), V(0, 0, 1)}, {V(0, 0, 1), V(-1, 0, 2), V(0, -1, 2)},
                      Contact::kCoplanar));
  // Degenerate (zero-area) triangles: reduced exactly to a segment or point.
  p.push_back(against_a("degenerate B: segment piercing A", "degenerate", V(1, 0.5, -1),
                        V(1, 0.5, 1), V(1, 0.5, 0.25), Contact::kSegment));
  p.push_back(against_a("degenerate B: segment missing A", "degenerate", V(3, 3, -1), V(3, 3, 1),
                        V(3, 3, 0), Contact::kDisjoint));
  p.push_back(against_a("degenerate B: segment in A's plane crossing A", "degenerate", V(1, 0.5, 0),
                        V(3, 0.5, 0), V(2, 0.5, 0), Contact::kCoplanar));
  p.push_back(against_a("degenerate B: segment in A's plane outside A", "degenerate", V(1, 2, 0),
                        V(3, 2, 0), V(2, 2, 0), Contact::kDisjoint));
  p.push_back(against_a("degenerate B: point inside A", "degenerate", V(1, 0.5, 0), V(1, 0.5, 0),
                        V(1, 0.5, 0), Contact::kSegment));
  p.push_back(against_a("degenerate B: point 1e-9 above A", "degenerate", V(1, 0.5, 1e-9),
                        V(1, 0.5, 1e-9), V(1, 0.5, 1e-9), Contact::kDisjoint));
  p.push_back(general("degenerate A (segment) piercing B", "degenerate",
                      {V(1, 0.5, -1), V(1, 0.5, 1), V(1, 0.5, 0.5)}, kA, Contact::kSegment));
  p.push_back(general("degenerate both: segments crossing", "degenerate",
                      {V(0, 0, 0), V(2, 0, 0), V(1, 0, 0)}, {V(1, -1, 0), V(1, 1, 0), V(1, 0.5, 0)},
                      Contact::kSegment));
  p.push_back(general("degenerate both: parallel segments", "degenerate",
                      {V(0, 0, 0), V(2, 0, 0), V(1, 0, 0)}, {V(0, 1, 0), V(2, 1, 0), V(1, 1, 0)},
                      Contact::kDisjoint));
  p.push_back(general("degenerate both: collinear overlapping segments", "degenerate",
                      {V(0, 0, 0), V(2, 2, 2), V(1, 1, 1)},
                      {V(1.5, 1.5, 1.5), V(3, 3, 3), V(4, 4, 4)}, Contact::kSegment));
  return p;
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
