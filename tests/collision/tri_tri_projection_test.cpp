// SPDX-License-Identifier: MIT
#include "collision/tri_tri_projection.h"

#include "collision/exact_predicates.h"
#include "tests/collision/tri_tri_test_support.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <set>
#include <string>

namespace softbench::collision::test {
namespace {

using Vec3 = Eigen::Vector3d;

/// Segment end points are interpolated in double along edges; for the well-conditioned pairs
/// checked here (designed and random, planes not within 1e-6 rad of parallel) they are within a
/// few hundred ulps of both triangles. 1e-9 of the pair's extent leaves a wide margin.
constexpr double kSegmentRelativeTolerance = 1e-9;

double extent(const TriPair& pair) {
  double e = 0.0;
  for (const auto* t : {&pair.a, &pair.b}) {
    for (const Vec3& v : *t) {
      e = std::max(e, v.cwiseAbs().maxCoeff());
    }
  }
  return std::max(e, 1e-300);
}

/// Sine of the angle between the planes (1 for degenerate triangles: not used then).
double plane_angle_sine(const TriPair& pair) {
  const Vec3 na = (pair.a[1] - pair.a[0]).cross(pair.a[2] - pair.a[0]);
  const Vec3 nb = (pair.b[1] - pair.b[0]).cross(pair.b[2] - pair.b[0]);
  if (na.norm() == 0.0 || nb.norm() == 0.0) {
    return 1.0;
  }
  return na.cross(nb).norm() / (na.norm() * nb.norm());
}

/// For a kSegment answer: both end points lie on both (proper) triangles within tolerance.
::testing::AssertionResult segment_on_both(const TriPair& pair, const TriTriResult& result) {
  const double tolerance = kSegmentRelativeTolerance * extent(pair);
  for (const Vec3* end : {&result.a, &result.b}) {
    for (const auto* t : {&pair.a, &pair.b}) {
      if (exactly_degenerate((*t)[0], (*t)[1], (*t)[2])) {
        continue;
      }
      const double distance =
          std::sqrt(squared_distance_to_triangle(*end, (*t)[0], (*t)[1], (*t)[2]));
      if (!(distance <= tolerance)) {
        return ::testing::AssertionFailure()
               << "end point (" << end->transpose() << ") is " << distance << " from a triangle";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

/// Figure 4.14's case of B against A's plane, from exact signs.
std::string figure_case(const TriPair& pair) {
  if (exactly_degenerate(pair.a[0], pair.a[1], pair.a[2])
      || exactly_degenerate(pair.b[0], pair.b[1], pair.b[2])) {
    return "degenerate";
  }
  int positive = 0;
  int negative = 0;
  for (const Vec3& q : pair.b) {
    const int s = orient3d(pair.a[1], pair.a[2], pair.a[0], q);
    positive += s > 0 ? 1 : 0;
    negative += s < 0 ? 1 : 0;
  }
  const int zeros = 3 - positive - negative;
  if (zeros == 3) {
    return "a";
  }
  if (positive == 3 || negative == 3) {
    return "b";
  }
  if (zeros == 2) {
    return "d";
  }
  if (zeros == 1) {
    return positive == 2 || negative == 2 ? "c" : "e";
  }
  return "f";
}

TEST(TriTriDesignedPairs, HandDerivedAnswersAgreeWithTheExactOracle) {
  const auto pairs = designed_pairs();
  ASSERT_GE(pairs.size(), 40u);
  for (const DesignedPair& d : pairs) {
    const TriPair& p = d.pair;
    EXPECT_EQ(exact_contact(p.a[0], p.a[1], p.a[2], p.b[0], p.b[1], p.b[2]), d.expected) << d.label;
  }
}

TEST(TriTriDesignedPairs, CoverEveryCaseOfFigure414WithRejectionsOnVAndW) {
  std::set<std::string> covered;
  for (const DesignedPair& d : designed_pairs()) {
    EXPECT_EQ(figure_case(d.pair), d.figure_case) << d.label;
    covered.insert(d.figure_case);
    for (const char* stage : {"rejected on V", "rejected on W", "passes V and W"}) {
      if (d.label.find(stage) != std::string::npos) {
        covered.insert(d.figure_case + ": " + stage);
      }
    }
  }
  for (const char* c : {"a", "b", "c", "d", "e", "f", "degenerate"}) {
    EXPECT_TRUE(covered.count(c)) << c;
  }
  for (const char* c : {"a", "c", "d", "e", "f"}) {
    for (const char* stage : {"rejected on V", "rejected on W", "passes V and W"}) {
      EXPECT_TRUE(covered.count(std::string(c) + ": " + stage)) << c << ": " << stage;
    }
  }
}

TEST(TriTriProjection, MatchesEveryDesignedPairWithASegmentOnBothTriangles) {
  for (const DesignedPair& d : designed_pairs()) {
    const TriTriResult result = run(tri_tri_projection, d.pair);
    EXPECT_EQ(result.contact, d.expected) << d.label;
    if (result.contact == TriTriContact::kSegment) {
      EXPECT_TRUE(segment_on_both(d.pair, result)) << d.label;
    }
    // The contact does not depend on which triangle is A.
    const TriPair swapped{d.pair.b, d.pair.a};
    EXPECT_EQ(run(tri_tri_projection, swapped).contact, d.expected) << d.label << " (swapped)";
  }
}

TEST(TriTriProjection, DesignedSegmentsHaveTheHandDerivedEndPoints) {
  // (f) B pierces A: L_B runs from the midpoint of Q0Q1 to that of Q0Q2, inside A.
  const TriTriResult pierce =
      tri_tri_projection(Vec3(0.5, 1.5, 0), Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0.5, 1),
                         Vec3(0.5, 0.3, -1), Vec3(1.5, 0.3, -1));
  ASSERT_EQ(pierce.contact, TriTriContact::kSegment);
  const double low = std::min(pierce.a.x(), pierce.b.x());
  const double high = std::max(pierce.a.x(), pierce.b.x());
  EXPECT_NEAR(low, 0.75, 1e-15);
  EXPECT_NEAR(high, 1.25, 1e-15);
  EXPECT_NEAR(pierce.a.y(), 0.4, 1e-15);
  // (d) an edge in A's plane crossing A's boundary: clipped at x + y = 2.
  const TriTriResult clipped =
      tri_tri_projection(Vec3(0.5, 1.5, 0), Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0.5, 0),
                         Vec3(3, 0.5, 0), Vec3(2, 0.5, -1));
  ASSERT_EQ(clipped.contact, TriTriContact::kSegment);
  EXPECT_NEAR(std::min(clipped.a.x(), clipped.b.x()), 1.0, 1e-15);
  EXPECT_NEAR(std::max(clipped.a.x(), clipped.b.x()), 1.5, 1e-15);
}

TEST(TriTriProjection, AgreesWithTheExactOracleOnRandomPairs) {
  const LabelledSet& set = random_set();
  const std::vector<TriPair>& pairs = *set.pairs;
  std::size_t hits = 0;
  std::size_t disagreements = 0;
  std::size_t segment_failures = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const TriTriResult result = run(tri_tri_projection, pairs[i]);
    hits += set.truth[i] ? 1 : 0;
    disagreements += result.intersect() != set.truth[i] ? 1 : 0;
    if (result.contact == TriTriContact::kSegment && plane_angle_sine(pairs[i]) > 1e-6) {
      segment_failures += segment_on_both(pairs[i], result) ? 0 : 1;
    }
  }
  const double fraction = static_cast<double>(hits) / static_cast<double>(pairs.size());
  std::cout << "[ random   ] " << pairs.size() << " pairs, " << 100.0 * fraction
            << " % intersect, projection disagrees on " << disagreements << "\n";
  RecordProperty("random_pairs", static_cast<int>(pairs.size()));
  RecordProperty("projection_disagreements", static_cast<int>(disagreements));
  EXPECT_GT(fraction, 0.25);
  EXPECT_LT(fraction, 0.35);
  EXPECT_EQ(disagreements, 0u);
  EXPECT_EQ(segment_failures, 0u);
}

TEST(TriTriProjection, AgreesWithTheExactOracleOnNearDegenerateFamilies) {
  reset_predicate_stats();
  for (std::size_t f = 0; f < families().size(); ++f) {
    const PairFamily& family = families()[f];
    const Disagreement d =
        count_disagreements(tri_tri_projection, family.pairs, family_truths()[f]);
    std::cout << "[ family   ] " << family.name << ": projection FP " << d.false_positives
              << ", FN " << d.false_negatives << " of " << family.pairs.size() << "\n";
    EXPECT_EQ(d.total(), 0u) << family.name;
  }
  const PredicateStats stats = predicate_stats();
  std::cout << "[ family   ] exact fallbacks: orient3d " << stats.orient3d_fallbacks
            << ", orient2d " << stats.orient2d_fallbacks << "\n";
}

TEST(TriTriProjection, AnswersDoNotDependOnAPowerOfTwoScale) {
  // Scaling every coordinate by 2^k is exact, so the exact answer cannot change; the scales
  // take the floating-point bounds from their usual range to overflow (2^500) and underflow
  // (2^-500), where only the exact paths may decide.
  const LabelledSet& set = random_set();
  const std::size_t count = std::min<std::size_t>(set.pairs->size(), 20000);
  for (const int exponent : {-500, -60, 60, 500}) {
    std::size_t disagreements = 0;
    for (std::size_t i = 0; i < count; ++i) {
      TriPair scaled = (*set.pairs)[i];
      for (auto* t : {&scaled.a, &scaled.b}) {
        for (Vec3& v : *t) {
          v = v * std::ldexp(1.0, exponent);
        }
      }
      disagreements += run(tri_tri_projection, scaled).intersect() != set.truth[i] ? 1 : 0;
    }
    EXPECT_EQ(disagreements, 0u) << "scale 2^" << exponent;
  }
}

TEST(TriTriProjection, IsSymmetricAndInvariantUnderVertexRelabelling) {
  // Every cyclic and reversed order of A's and B's vertices gives the same contact.
  for (const DesignedPair& d : designed_pairs()) {
    const auto& a = d.pair.a;
    const auto& b = d.pair.b;
    for (int r = 0; r < 3; ++r) {
      for (const bool reverse : {false, true}) {
        const int i0 = r, i1 = reverse ? (r + 2) % 3 : (r + 1) % 3,
                  i2 = reverse ? (r + 1) % 3 : (r + 2) % 3;
        const TriTriResult result = tri_tri_projection(a[i0], a[i1], a[i2], b[i2], b[i0], b[i1]);
        EXPECT_EQ(result.contact, d.expected) << d.label << " r=" << r << " reverse=" << reverse;
      }
    }
  }
}

}  // namespace
}  // namespace softbench::collision::test
