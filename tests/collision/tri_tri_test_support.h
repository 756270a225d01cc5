// SPDX-License-Identifier: MIT
#pragma once

// Shared helpers of the triangle-triangle test files: running a test over a pair set against the
// exact oracle, and the pair-set sizes (smaller in Debug builds so the suite stays fast).

#include "collision/tri_tri_result.h"
#include "tests/collision/exact_oracle.h"
#include "tests/collision/pair_sets.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace softbench::collision::test {

#ifdef NDEBUG
inline constexpr std::size_t kRandomPairCount = 1'000'000;
inline constexpr std::size_t kFamilyPairCount = 100'000;
#else
inline constexpr std::size_t kRandomPairCount = 50'000;
inline constexpr std::size_t kFamilyPairCount = 5'000;
#endif
inline constexpr std::uint64_t kRandomSeed = 20240611;
inline constexpr std::uint64_t kFamilySeed = 7;

using TriTriFunction = TriTriTest*;

inline TriTriResult run(TriTriFunction test, const TriPair& pair) {
  return test(pair.a[0], pair.a[1], pair.a[2], pair.b[0], pair.b[1], pair.b[2]);
}

/// The pair sets with their exact answers, built once per test binary.
struct LabelledSet {
  const std::vector<TriPair>* pairs = nullptr;
  std::vector<bool> truth;
};
const LabelledSet& random_set();
const std::vector<PairFamily>& families();
const std::vector<std::vector<bool>>& family_truths();

struct Disagreement {
  std::size_t false_positives = 0;
  std::size_t false_negatives = 0;
  std::size_t total() const { return false_positives + false_negatives; }
};
Disagreement count_disagreements(TriTriFunction test,
                                 const std::vector<TriPair>& pairs,
                                 const std::vector<bool>& truth);

}  // namespace softbench::collision::test
