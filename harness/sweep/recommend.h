// SPDX-License-Identifier: MIT
#pragma once

#include "harness/sweep/sweep.h"
#include "scenes/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace softbench::harness {

/// The choice `softbench recommend` makes from a scene's requirements and its sweep.
struct Recommendation {
  std::optional<SweepRecord> choice;  ///< the fastest run meeting every requirement
  std::string explanation;            ///< Markdown: the requirements, the choice, the near misses
};

/// Why `record` misses `requirements` ("" if it meets them): unstable, too slow, or an output
/// off by more than the accuracy.
std::string shortfall(const SweepRecord& record, const scenes::Requirements& requirements);

/// Picks, among `records` (a sweep of the scene), the fastest that meets the requirements, and
/// explains the choice: what each model's best run missed by.
Recommendation recommend(const scenes::Requirements& requirements,
                         const std::vector<SweepRecord>& records);

}  // namespace softbench::harness
