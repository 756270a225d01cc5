// SPDX-License-Identifier: MIT
#include "collision/tri_tri_batch.h"

#include "collision/tri_tri_projection.h"
#include "tests/collision/tri_tri_test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <vector>

namespace softbench::collision::test {
namespace {

/// Runs the batch over `pairs` and counts pairs whose answer differs from the scalar exact test.
std::size_t batch_mismatches(const std::vector<TriPair>& pairs, const char* name) {
  TriangleSoA a;
  TriangleSoA b;
  a.reserve(pairs.size());
  b.reserve(pairs.size());
  for (const TriPair& p : pairs) {
    a.push_back(p.a[0], p.a[1], p.a[2]);
    b.push_back(p.b[0], p.b[1], p.b[2]);
  }
  std::vector<std::uint8_t> answer(pairs.size());
  const BatchStats stats = tri_tri_batch(a, b, answer);
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    mismatches += (answer[i] != 0) != run(tri_tri_projection, pairs[i]).intersect() ? 1 : 0;
  }
  std::cout << "[ batch    ] " << name << ": " << stats.exact_fallbacks << " of " << stats.pairs
            << " lanes fell back to the exact scalar test\n";
  return mismatches;
}

TEST(TriTriBatch, EqualsTheScalarProjectionTestOnDesignedPairs) {
  std::vector<TriPair> pairs;
  for (int repeat = 0; repeat < 3; ++repeat) {  // more than one block, and a ragged tail
    for (const DesignedPair& d : designed_pairs()) {
      pairs.push_back(d.pair);
    }
  }
  EXPECT_EQ(batch_mismatches(pairs, "designed"), 0u);
}

TEST(TriTriBatch, EqualsTheScalarProjectionTestOnRandomPairs) {
  EXPECT_EQ(batch_mismatches(*random_set().pairs, "random"), 0u);
}

TEST(TriTriBatch, EqualsTheScalarProjectionTestOnNearDegenerateFamilies) {
  for (const PairFamily& family : families()) {
    EXPECT_EQ(batch_mismatches(family.pairs, family.name.c_str()), 0u) << family.name;
  }
}

TEST(TriTriBatch, EqualsTheScalarProjectionTestOnScaledPairs) {
  // Beyond the lanes' overflow and underflow guards every lane is left to the scalar test.
  const std::vector<TriPair>& random = *random_set().pairs;
  for (const int exponent : {-500, 500}) {
    std::vector<TriPair> pairs(random.begin(), random.begin() + 4001);
    for (TriPair& p : pairs) {
      for (auto* t : {&p.a, &p.b}) {
        for (Eigen::Vector3d& v : *t) {
          v *= std::ldexp(1.0, exponent);
        }
      }
    }
    EXPECT_EQ(batch_mismatches(pairs, "scaled"), 0u) << "scale 2^" << exponent;
  }
}

TEST(TriTriBatch, EveryRaggedTailLengthRunsThroughTheLanesWithTheSameAnswers) {
  // Sizes 1 to 3 blocks, so that every tail length (padded into a block of its own) occurs for
  // both lane widths, on pairs that intersect and pairs that do not.
  const std::vector<TriPair>& random = *random_set().pairs;
  for (std::size_t size = 1; size <= 24; ++size) {
    const std::vector<TriPair> pairs(random.begin() + static_cast<std::ptrdiff_t>(size),
                                     random.begin() + static_cast<std::ptrdiff_t>(2 * size));
    EXPECT_EQ(batch_mismatches(pairs, "ragged"), 0u) << "size " << size;
  }
}

TEST(TriTriBatch, EmptyInputIsFine) {
  const TriangleSoA none;
  std::vector<std::uint8_t> answer;
  EXPECT_EQ(tri_tri_batch(none, none, answer).pairs, 0u);
}

}  // namespace
}  // namespace softbench::collision::test
