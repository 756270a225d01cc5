// SPDX-License-Identifier: MIT
#include "collision/tri_tri_batch.h"

#include "collision/exact_predicates.h"
#include "collision/tri_tri_batch_lanes.h"
#include "collision/tri_tri_projection.h"

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <cstring>

namespace softbench::collision {
namespace {

using namespace detail;

/// Lanes as GCC generic vectors of 4 doubles: one AVX2 register, two SSE2 registers in the
/// baseline build. (8-lane generic vectors compile to scalar comparisons with GCC 12; the
/// AVX-512 kernel uses intrinsics instead, collision/tri_tri_batch_avx512.cpp.)
struct VectorOps {
  typedef double V __attribute__((vector_size(32)));
  typedef std::int64_t Mask __attribute__((vector_size(32)));  // 0 / -1, what < yields
  static constexpr std::size_t kLanes = 4;
  SOFTBENCH_LANES_INLINE static V load(const double* p) {
    V v;
    std::memcpy(&v, p, sizeof(V));
    return v;
  }
  SOFTBENCH_LANES_INLINE static Mask greater(V a, V b) { return a > b; }
  SOFTBENCH_LANES_INLINE static Mask less(V a, V b) { return a < b; }
  SOFTBENCH_LANES_INLINE static V select(Mask m, V a, V b) { return m ? a : b; }
  SOFTBENCH_LANES_INLINE static V abs(V v) { return v < 0.0 ? -v : v; }
  SOFTBENCH_LANES_INLINE static V max(V a, V b) { return a > b ? a : b; }
  SOFTBENCH_LANES_INLINE static V min(V a, V b) { return a < b ? a : b; }
  SOFTBENCH_LANES_INLINE static bool lane(Mask m, std::size_t l) { return m[l] != 0; }
};

Columns columns(const TriangleSoA& t) {
  return {t.x0.data(), t.y0.data(), t.z0.data(), t.x1.data(), t.y1.data(),
          t.z1.data(), t.x2.data(), t.y2.data(), t.z2.data()};
}

using Kernel = void (*)(const Columns&, const Columns&, std::size_t, std::uint8_t*);

void classify_portable(const Columns& a,
                       const Columns& b,
                       std::size_t count,
                       std::uint8_t* status) {
  classify_all<VectorOps>(a, b, count, status);
}

#if defined(__x86_64__) || defined(__i386__)
// The same loop for AVX2 (no FMA: the bounds assume separately rounded operations; this file is
// compiled with -ffp-contract=off), chosen at run time with the AVX-512 one: the project does
// not build with -march=native.
__attribute__((target("avx2"))) void classify_avx2(const Columns& a,
                                                   const Columns& b,
                                                   std::size_t count,
                                                   std::uint8_t* status) {
  classify_all<VectorOps>(a, b, count, status);
}

struct Dispatch {
  Kernel kernel;
  std::size_t lanes;
};

Dispatch dispatch() {
  static const Dispatch chosen =
      __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq")
          ? Dispatch{classify_avx512, 8}
          : (__builtin_cpu_supports("avx2") ? Dispatch{classify_avx2, 4}
                                            : Dispatch{classify_portable, 4});
  return chosen;
}
#else
struct Dispatch {
  Kernel kernel;
  std::size_t lanes;
};

Dispatch dispatch() {
  return {classify_portable, 4};
}
#endif

}  // namespace

void TriangleSoA::reserve(std::size_t n) {
  for (auto* v : {&x0, &y0, &z0, &x1, &y1, &z1, &x2, &y2, &z2}) {
    v->reserve(n);
  }
}

void TriangleSoA::clear() {
  for (auto* v : {&x0, &y0, &z0, &x1, &y1, &z1, &x2, &y2, &z2}) {
    v->clear();
  }
}

void TriangleSoA::push_back(const Eigen::Vector3d& v0,
                            const Eigen::Vector3d& v1,
                            const Eigen::Vector3d& v2) {
  x0.push_back(v0.x());
  y0.push_back(v0.y());
  z0.push_back(v0.z());
  x1.push_back(v1.x());
  y1.push_back(v1.y());
  z1.push_back(v1.z());
  x2.push_back(v2.x());
  y2.push_back(v2.y());
  z2.push_back(v2.z());
}

Eigen::Vector3d TriangleSoA::vertex(std::size_t i, int k) const {
  switch (k) {
    case 0:
      return {x0[i], y0[i], z0[i]};
    case 1:
      return {x1[i], y1[i], z1[i]};
    default:
      return {x2[i], y2[i], z2[i]};
  }
}

namespace {

/// Lanes of the ragged tail [first, size) copied into one full block, padded with copies of the
/// tail's last pair, so that the tail runs through the kernel too rather than the scalar test
/// (on leaf-sized batches of 10-100 pairs the tail is a large share).
struct TailBlock {
  static constexpr std::size_t kMaxLanes = 8;
  double a[9][kMaxLanes];
  double b[9][kMaxLanes];

  static Columns columns_of(const double (&c)[9][kMaxLanes]) {
    return {c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]};
  }
  static void fill(double (&c)[9][kMaxLanes],
                   const TriangleSoA& t,
                   std::size_t first,
                   std::size_t lanes) {
    const std::vector<double>* const source[9] = {&t.x0, &t.y0, &t.z0, &t.x1, &t.y1,
                                                  &t.z1, &t.x2, &t.y2, &t.z2};
    for (std::size_t l = 0; l < lanes; ++l) {
      const std::size_t i = std::min(first + l, t.size() - 1);
      for (int k = 0; k < 9; ++k) {
        c[k][l] = (*source[k])[i];
      }
    }
  }
};

}  // namespace

BatchStats tri_tri_batch(const TriangleSoA& a,
                         const TriangleSoA& b,
                         std::span<std::uint8_t> intersect) {
  assert(a.size() == b.size() && intersect.size() >= a.size());
  BatchStats stats;
  stats.pairs = a.size();
  const Dispatch d = dispatch();
  const std::size_t blocked = a.size() / d.lanes * d.lanes;
  d.kernel(columns(a), columns(b), blocked, intersect.data());
  if (blocked < a.size()) {
    TailBlock tail;
    TailBlock::fill(tail.a, a, blocked, d.lanes);
    TailBlock::fill(tail.b, b, blocked, d.lanes);
    std::uint8_t status[TailBlock::kMaxLanes];
    d.kernel(TailBlock::columns_of(tail.a), TailBlock::columns_of(tail.b), d.lanes, status);
    std::copy(status, status + (a.size() - blocked), intersect.data() + blocked);
  }
  // The lanes the bounds left undecided (rare: memchr finds them faster than a byte loop), by
  // the scalar exact test.
  for (std::size_t i = 0; i < a.size(); ++i) {
    const void* found = std::memchr(intersect.data() + i, kLaneUndecided, a.size() - i);
    if (found == nullptr) {
      break;
    }
    i = static_cast<std::size_t>(static_cast<const std::uint8_t*>(found) - intersect.data());
    ++stats.exact_fallbacks;
    intersect[i] = tri_tri_projection(a.vertex(i, 0), a.vertex(i, 1), a.vertex(i, 2),
                                      b.vertex(i, 0), b.vertex(i, 1), b.vertex(i, 2))
                           .intersect()
                       ? kLaneIntersect
                       : kLaneDisjoint;
  }
  return stats;
}

}  // namespace softbench::collision
