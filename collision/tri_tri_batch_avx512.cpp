// SPDX-License-Identifier: MIT
// The AVX-512 lane kernel of collision/tri_tri_batch.cpp: eight pairs per block in one zmm
// register per quantity, comparisons into mask registers. This file alone is compiled with
// -mavx512f -mavx512dq (collision/CMakeLists.txt) and is only called after a run-time CPU check;
// it defines nothing but classify_avx512, so no AVX-512 code can stand in for an inline function
// of the baseline build.
#include "collision/tri_tri_batch_lanes.h"

#if defined(__x86_64__)
#include <immintrin.h>

#include <cstdint>

namespace softbench::collision::detail {
namespace {

/// Eight lanes: plain GCC vectors for the arithmetic (__m512d itself carries may_alias, which a
/// template argument drops), intrinsics for the comparisons into mask registers and the blends.
struct Avx512Ops {
  typedef double V __attribute__((vector_size(64)));
  typedef std::int64_t Bits __attribute__((vector_size(64)));
  using Mask = __mmask8;
  static constexpr std::size_t kLanes = 8;
  SOFTBENCH_LANES_INLINE static V load(const double* p) { return V(_mm512_loadu_pd(p)); }
  SOFTBENCH_LANES_INLINE static Mask greater(V a, V b) {
    return _mm512_cmp_pd_mask(__m512d(a), __m512d(b), _CMP_GT_OQ);
  }
  SOFTBENCH_LANES_INLINE static Mask less(V a, V b) {
    return _mm512_cmp_pd_mask(__m512d(a), __m512d(b), _CMP_LT_OQ);
  }
  SOFTBENCH_LANES_INLINE static V select(Mask m, V a, V b) {
    return V(_mm512_mask_blend_pd(m, __m512d(b), __m512d(a)));
  }
  SOFTBENCH_LANES_INLINE static V abs(V v) { return V(Bits(v) & INT64_MAX); }
  SOFTBENCH_LANES_INLINE static V max(V a, V b) { return select(greater(a, b), a, b); }
  SOFTBENCH_LANES_INLINE static V min(V a, V b) { return select(less(a, b), a, b); }
  SOFTBENCH_LANES_INLINE static bool lane(Mask m, std::size_t l) { return ((m >> l) & 1u) != 0; }
};

}  // namespace

void classify_avx512(const Columns& a, const Columns& b, std::size_t count, std::uint8_t* status) {
  classify_all<Avx512Ops>(a, b, count, status);
}

}  // namespace softbench::collision::detail
#endif  // __x86_64__
