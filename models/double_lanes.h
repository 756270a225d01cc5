// SPDX-License-Identifier: MIT
#pragma once

#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace softbench {

/// Two doubles in one SSE2 register (GCC's and Clang's vector extension: portable, and plain
/// scalar code where the target has no such registers): the mass-spring loops take two springs
/// at a time, the block products two vectors at a time.
using Pair = double __attribute__((vector_size(16)));
/// Four doubles: one AVX register where the build targets it (x86-64-v3), two SSE2 ones
/// otherwise. The block products take four vectors at a time, shape matching's moments four
/// members.
using Quad = double __attribute__((vector_size(32)));

inline Pair load_pair(const double* at) {
  Pair pair;
  std::memcpy(&pair, at, sizeof(pair));
  return pair;
}

inline Quad load_quad(const double* at) {
  Quad quad;
  std::memcpy(&quad, at, sizeof(quad));
  return quad;
}

/// Four floats widened to four doubles (one conversion instruction on x86-64-v3): a matrix kept
/// in single precision, read where its traffic, not its arithmetic, bounds a loop.
inline Quad load_quad(const float* at) {
  using FloatQuad = float __attribute__((vector_size(16)));
  FloatQuad quad;
  std::memcpy(&quad, at, sizeof(quad));
  return __builtin_convertvector(quad, Quad);
}

inline void store_pair(double* at, Pair pair) {
  std::memcpy(at, &pair, sizeof(pair));
}

/// `value` in every lane.
inline Quad broadcast_quad(double value) {
  return Quad{value, value, value, value};
}

inline void store_quad(double* at, Quad quad) {
  std::memcpy(at, &quad, sizeof(quad));
}

/// Lane by lane. SSE2's one instruction for both where the target has it: std::sqrt may set
/// errno, so the compiler keeps a check and a library call per lane.
inline Pair sqrt_pair(Pair pair) {
#if defined(__SSE2__)
  return _mm_sqrt_pd(pair);
#else
  return Pair{std::sqrt(pair[0]), std::sqrt(pair[1])};
#endif
}

}  // namespace softbench
