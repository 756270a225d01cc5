// SPDX-License-Identifier: MIT
#include "tests/collision/tri_tri_test_support.h"

namespace softbench::collision::test {
namespace {

std::vector<bool> oracle_answers(const std::vector<TriPair>& pairs) {
  std::vector<bool> truth(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const TriPair& p = pairs[i];
    truth[i] = exact_intersect(p.a[0], p.a[1], p.a[2], p.b[0], p.b[1], p.b[2]);
  }
  return truth;
}

}  // namespace

const LabelledSet& random_set() {
  static const std::vector<TriPair> pairs = random_pairs(kRandomPairCount, kRandomSeed);
  static const LabelledSet set{&pairs, oracle_answers(pairs)};
  return set;
}

const std::vector<PairFamily>& families() {
  static const std::vector<PairFamily> sets =
      near_degenerate_families(kFamilyPairCount, kFamilySeed);
  return sets;
}

const std::vector<std::vector<bool>>& family_truths() {
  static const std::vector<std::vector<bool>> truths = [] {
    std::vector<std::vector<bool>> result;
    for (const PairFamily& family : families()) {
      result.push_back(oracle_answers(family.pairs));
    }
    return result;
  }();
  return truths;
}

Disagreement count_disagreements(TriTriFunction test,
                                 const std::vector<TriPair>& pairs,
                                 const std::vector<bool>& truth) {
  Disagreement d;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const bool answer = run(test, pairs[i]).intersect();
    d.false_positives += answer && !truth[i] ? 1 : 0;
    d.false_negatives += !answer && truth[i] ? 1 : 0;
  }
  return d;
}

}  // namespace softbench::collision::test
