// SPDX-License-Identifier: MIT
// The peers of the projection method (Moeller 1997, Guigue-Devillers 2003, plain double): they
// must agree with the exact oracle on generic random pairs; on designed singular pairs and
// near-degenerate families their disagreements are measured and reported, not asserted.
#include "collision/tri_tri_guigue.h"
#include "collision/tri_tri_moller.h"
#include "tests/collision/tri_tri_test_support.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

namespace softbench::collision::test {
namespace {

struct Peer {
  const char* name;
  TriTriFunction test;
};
const Peer kPeers[] = {{"moller", tri_tri_moller}, {"guigue_devillers", tri_tri_guigue}};

/// Segment ends of the peers come from the same edge interpolation as the projection method's:
/// on generic random pairs (planes not within 1e-6 rad of parallel) within 1e-9 of the extent.
constexpr double kPeersSegmentRelativeTolerance = 1e-9;

bool degenerate(const TriPair& p) {
  return exactly_degenerate(p.a[0], p.a[1], p.a[2]) || exactly_degenerate(p.b[0], p.b[1], p.b[2]);
}

TEST(TriTriPeers, AgreeWithTheExactOracleOnGenericRandomPairs) {
  // The recipe clamps B to the unit cube, which now and then flattens B onto a cube edge: those
  // degenerate pairs are outside the peers' contract and are reported, not asserted.
  const LabelledSet& set = random_set();
  for (const Peer& peer : kPeers) {
    std::size_t wrong_proper = 0;
    std::size_t wrong_degenerate = 0;
    std::size_t degenerate_pairs = 0;
    for (std::size_t i = 0; i < set.pairs->size(); ++i) {
      const TriPair& p = (*set.pairs)[i];
      const bool is_degenerate = degenerate(p);
      degenerate_pairs += is_degenerate ? 1 : 0;
      if (run(peer.test, p).intersect() != set.truth[i]) {
        (is_degenerate ? wrong_degenerate : wrong_proper) += 1;
      }
    }
    std::cout << "[ random   ] " << peer.name << ": wrong on " << wrong_proper
              << " proper pairs of " << set.pairs->size() - degenerate_pairs << ", on "
              << wrong_degenerate << " degenerate pairs of " << degenerate_pairs << "\n";
    RecordProperty(std::string(peer.name) + "_random_disagreements",
                   static_cast<int>(wrong_proper + wrong_degenerate));
    EXPECT_EQ(wrong_proper, 0u) << peer.name;
  }
}

TEST(TriTriPeers, SegmentsLieOnBothTrianglesForGenericPairs) {
  const LabelledSet& set = random_set();
  const std::size_t checked = std::min<std::size_t>(set.pairs->size(), 20000);
  for (const Peer& peer : kPeers) {
    std::size_t failures = 0;
    for (std::size_t i = 0; i < checked; ++i) {
      const TriPair& p = (*set.pairs)[i];
      const TriTriResult r = run(peer.test, p);
      if (r.contact != TriTriContact::kSegment) {
        continue;
      }
      for (const Eigen::Vector3d* end : {&r.a, &r.b}) {
        for (const auto* t : {&p.a, &p.b}) {
          const double distance =
              std::sqrt(squared_distance_to_triangle(*end, (*t)[0], (*t)[1], (*t)[2]));
          failures += distance <= kPeersSegmentRelativeTolerance ? 0 : 1;
        }
      }
    }
    EXPECT_EQ(failures, 0u) << peer.name;
  }
}

TEST(TriTriPeers, ReportDisagreementsOnDesignedPairsAndNearDegenerateFamilies) {
  for (const Peer& peer : kPeers) {
    std::size_t family_disagreements = 0;
    int wrong = 0;
    std::string labels;
    int proper = 0;
    for (const DesignedPair& d : designed_pairs()) {
      if (d.figure_case == "degenerate") {
        continue;  // outside the peers' contract
      }
      ++proper;
      if (run(peer.test, d.pair).intersect() != (d.expected != TriTriContact::kDisjoint)) {
        ++wrong;
        labels += "\n    " + d.label;
      }
    }
    std::cout << "[ designed ] " << peer.name << ": wrong on " << wrong << " of " << proper
              << labels << "\n";
    // Every designed pair that is not degenerate is clear of round-off: a plain-double method
    // must get each one right.
    EXPECT_EQ(wrong, 0) << peer.name << labels;
    RecordProperty(std::string(peer.name) + "_designed_wrong", wrong);
    for (std::size_t f = 0; f < families().size(); ++f) {
      const Disagreement d =
          count_disagreements(peer.test, families()[f].pairs, family_truths()[f]);
      const double rate =
          100.0 * static_cast<double>(d.total()) / static_cast<double>(families()[f].pairs.size());
      std::cout << "[ family   ] " << peer.name << " / " << families()[f].name << ": " << rate
                << " % disagree (FP " << d.false_positives << ", FN " << d.false_negatives << ")\n";
      // On pairs built to sit on round-off, a plain-double method errs on some (up to 19% for
      // Moeller's where an edge lies in the other plane), but it is still a triangle test: it
      // answers most of them right.
      constexpr double kMostDisagreement = 25.0;  // %
      EXPECT_LT(rate, kMostDisagreement) << peer.name << " / " << families()[f].name;
      family_disagreements += d.total();
    }
    // And the reason the exact predicates exist: on these families plain doubles do err.
    EXPECT_GT(family_disagreements, 0U) << peer.name;
  }
}

}  // namespace
}  // namespace softbench::collision::test
