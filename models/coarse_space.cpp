// SPDX-License-Identifier: MIT
#include "models/coarse_space.h"

#include "models/cholmod_factor.h"
#include "models/eisenstat_cg.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <utility>

namespace softbench {

std::vector<int> grow_aggregates(const BlockPattern& pattern, int target) {
  const int n = pattern.num_vertices();
  if (target <= 0 || target >= n) {
    return std::vector<int>(static_cast<std::size_t>(n), 0);
  }
  std::vector<int> aggregate_of(static_cast<std::size_t>(n), -1);
  std::vector<int> sizes;
  std::vector<int> queue;
  queue.reserve(static_cast<std::size_t>(n));
  for (int seed = 0; seed < n; ++seed) {
    if (aggregate_of[static_cast<std::size_t>(seed)] >= 0) {
      continue;
    }
    const auto id = static_cast<int>(sizes.size());
    queue.assign(1, seed);
    aggregate_of[static_cast<std::size_t>(seed)] = id;
    for (std::size_t head = 0; head < queue.size() && static_cast<int>(queue.size()) < target;
         ++head) {
      for (const int neighbour : pattern.neighbours(queue[head])) {
        if (static_cast<int>(queue.size()) < target
            && aggregate_of[static_cast<std::size_t>(neighbour)] < 0) {
          aggregate_of[static_cast<std::size_t>(neighbour)] = id;
          queue.push_back(neighbour);
        }
      }
    }
    sizes.push_back(static_cast<int>(queue.size()));
  }
  // A small aggregate joins its largest neighbour (through `joined`, followed to the end).
  std::vector<int> joined(sizes.size());
  for (std::size_t g = 0; g < joined.size(); ++g) {
    joined[g] = static_cast<int>(g);
  }
  const auto root = [&joined](int g) {
    while (joined[static_cast<std::size_t>(g)] != g) {
      g = joined[static_cast<std::size_t>(g)];
    }
    return g;
  };
  for (int v = 0; v < n; ++v) {
    const int own = root(aggregate_of[static_cast<std::size_t>(v)]);
    if (4 * sizes[static_cast<std::size_t>(own)] >= target) {
      continue;
    }
    int best = -1;
    for (const int neighbour : pattern.neighbours(v)) {
      const int other = root(aggregate_of[static_cast<std::size_t>(neighbour)]);
      if (other != own
          && (best < 0
              || sizes[static_cast<std::size_t>(other)] > sizes[static_cast<std::size_t>(best)])) {
        best = other;
      }
    }
    if (best >= 0) {
      joined[static_cast<std::size_t>(own)] = best;
      sizes[static_cast<std::size_t>(best)] += sizes[static_cast<std::size_t>(own)];
    }
  }
  std::vector<int> renamed(sizes.size(), -1);
  int next = 0;
  for (int& a : aggregate_of) {
    const auto r = static_cast<std::size_t>(root(a));
    if (renamed[r] < 0) {
      renamed[r] = next++;
    }
    a = renamed[r];
  }
  return aggregate_of;
}

CoarseSpace::CoarseSpace(const BlockPattern& pattern, std::vector<int> aggregate_of)
    : aggregate_of_(std::move(aggregate_of)) {
  const int n = pattern.num_vertices();
  if (aggregate_of_.size() != static_cast<std::size_t>(n)) {
    throw std::invalid_argument("CoarseSpace: one aggregate per vertex");
  }
  num_aggregates_ =
      aggregate_of_.empty() ? 0 : 1 + *std::max_element(aggregate_of_.begin(), aggregate_of_.end());
  touch_offsets_.assign(static_cast<std::size_t>(n) + 1, 0);
  std::vector<int> touched;
  for (int v = 0; v < n; ++v) {
    touched.clear();
    for (const int neighbour : pattern.neighbours(v)) {
      touched.push_back(aggregate(neighbour));
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    for (const int neighbour : pattern.neighbours(v)) {
      slot_touch_.push_back(
          static_cast<int>(std::lower_bound(touched.begin(), touched.end(), aggregate(neighbour))
                           - touched.begin()));
    }
    touch_aggregates_.insert(touch_aggregates_.end(), touched.begin(), touched.end());
    touch_offsets_[static_cast<std::size_t>(v) + 1] = static_cast<int>(touch_aggregates_.size());
  }
  full_blocks_.assign(9 * touch_aggregates_.size(), 0.0);
  upper_blocks_.assign(9 * touch_aggregates_.size(), 0.0);

  // E's pattern: a full 3x3 block for each pair of aggregates some vertex couples.
  // Each touch k of a vertex of aggregate g to aggregate h, as f(k, g, h).
  const auto for_each_touch = [&](const auto& f) {
    for (int v = 0; v < n; ++v) {
      for (int k = touch_offsets_[static_cast<std::size_t>(v)];
           k < touch_offsets_[static_cast<std::size_t>(v) + 1]; ++k) {
        f(static_cast<std::size_t>(k), aggregate(v),
          touch_aggregates_[static_cast<std::size_t>(k)]);
      }
    }
  };
  std::vector<Eigen::Triplet<double>> triplets;
  for_each_touch([&](std::size_t, int g, int h) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        triplets.emplace_back(3 * g + i, 3 * h + j, 0.0);
      }
    }
  });
  coarse_.resize(3 * num_aggregates_, 3 * num_aggregates_);
  coarse_.setFromTriplets(triplets.begin(), triplets.end());
  coarse_.makeCompressed();
  coarse_entries_.resize(3 * touch_aggregates_.size());
  for_each_touch([&](std::size_t k, int g, int h) {
    for (int j = 0; j < 3; ++j) {
      const int column = 3 * h + j;
      const int* rows = coarse_.innerIndexPtr();
      const int begin = coarse_.outerIndexPtr()[column];
      const int end = coarse_.outerIndexPtr()[column + 1];
      coarse_entries_[3 * k + static_cast<std::size_t>(j)] =
          static_cast<int>(std::lower_bound(rows + begin, rows + end, 3 * g) - rows);
    }
  });
  factor_ = std::make_unique<CholmodFactor>(coarse_,
                                            /*supernodal=*/coarse_.rows() >= kSupernodalFrom);
  coarse_vector_.setZero(3 * num_aggregates_);
  solution_.setZero(3 * num_aggregates_);
  range_sums_.assign(static_cast<std::size_t>(kMaxRanges) * 3 * num_aggregates_, 0.0);
}

CoarseSpace::~CoarseSpace() = default;

bool CoarseSpace::load(const BlockPattern& a) {
  load_blocks(a);
  return finish_load();
}

void CoarseSpace::load_blocks(const BlockPattern& a) {
  over_ranges(a.part_offsets(), [&](int first, int last) {
    for (int v = first; v < last; ++v) {
      const auto degree = static_cast<int>(a.neighbours(v).size());
      const int own = a.own_slot(v);
      const double* column = a.matrix().valuePtr() + a.column_values_begin(v);
      const int begin = touch_offsets_[static_cast<std::size_t>(v)];
      const int end = touch_offsets_[static_cast<std::size_t>(v) + 1];
      std::fill(full_blocks_.begin() + 9 * begin, full_blocks_.begin() + 9 * end, 0.0);
      std::fill(upper_blocks_.begin() + 9 * begin, upper_blocks_.begin() + 9 * end, 0.0);
      // slot_touch_ runs parallel to the pattern's neighbour lists.
      const int* touch_of = slot_touch_.data() + (a.neighbours(v).data() - a.neighbours(0).data());
      // A run of slots on one touch, all before or all after v's own slot, is summed in
      // registers and added to its block once (the slots after v into U W's; A W's gets U W's
      // at the end): a whole-body aggregate is one run on each side of the diagonal.
      const auto stride = static_cast<std::ptrdiff_t>(3 * degree);
      int slot = 0;
      while (slot < degree) {
        const int touch = touch_of[slot];
        const bool after = slot > own;
        // Entry (k, i) of A_vn is column k's strip of n, entry i; the blocks keep it at k + 3 i
        // (column-major).
        double sum[9] = {};
        for (; slot < degree && touch_of[slot] == touch && (slot > own) == after; ++slot) {
          const double* entries = column + 3 * slot;
          for (int k = 0; k < 3; ++k) {
            for (int i = 0; i < 3; ++i) {
              sum[k + 3 * i] += entries[stride * k + i];
            }
          }
        }
        double* block = (after ? upper_blocks_ : full_blocks_).data() + 9 * (begin + touch);
        for (int e = 0; e < 9; ++e) {
          block[e] += sum[e];
        }
      }
      for (int e = 9 * begin; e < 9 * end; ++e) {
        full_blocks_[static_cast<std::size_t>(e)] += upper_blocks_[static_cast<std::size_t>(e)];
      }
    }
    return RangeSums{};
  });
}

bool CoarseSpace::finish_load() {
  // E's block (g, h) sums A W's blocks (v, h) over the vertices v of g.
  double* values = coarse_.valuePtr();
  std::fill(values, values + coarse_.nonZeros(), 0.0);
  for (std::size_t k = 0; k < touch_aggregates_.size(); ++k) {
    const double* block = full_blocks_.data() + 9 * k;
    for (int j = 0; j < 3; ++j) {
      const int at = coarse_entries_[3 * k + static_cast<std::size_t>(j)];
      for (int i = 0; i < 3; ++i) {
        values[at + i] += block[i + 3 * j];
      }
    }
  }
  return factor_->factorize(coarse_);
}

void CoarseSpace::clear_restriction(std::span<const int> ranges) {
  // Only the slices of the ranges in use (the buffer has room for kMaxRanges).
  std::fill_n(range_sums_.begin(),
              (ranges.size() - 1) * static_cast<std::size_t>(coarse_vector_.size()), 0.0);
}

double* CoarseSpace::restriction_slice(std::span<const int> ranges, int first, int last) {
  std::size_t range = 0;
  while (ranges[range] != first || ranges[range + 1] != last) {
    ++range;
  }
  return range_sums_.data() + range * static_cast<std::size_t>(coarse_vector_.size());
}

void CoarseSpace::finish_restriction(std::span<const int> ranges) {
  const Eigen::Index size = coarse_vector_.size();
  coarse_vector_.setZero();
  for (std::size_t range = 0; range + 1 < ranges.size(); ++range) {
    coarse_vector_ += Eigen::Map<const Eigen::VectorXd>(
        range_sums_.data() + range * static_cast<std::size_t>(size), size);
  }
}

void CoarseSpace::restrict_to_coarse(std::span<const int> ranges, const double* y) {
  clear_restriction(ranges);
  over_ranges(ranges, [&](int first, int last) {
    double* slice = restriction_slice(ranges, first, last);
    for (int v = first; v < last; ++v) {
      double* o = slice + 3 * aggregate(v);
      o[0] += y[3 * v];
      o[1] += y[3 * v + 1];
      o[2] += y[3 * v + 2];
    }
    return RangeSums{};
  });
  finish_restriction(ranges);
}

void CoarseSpace::solve() {
  factor_->solve(coarse_vector_, solution_);
  coarse_vector_.swap(solution_);
}

std::size_t CoarseSpace::memory_bytes() const {
  return (full_blocks_.capacity() + upper_blocks_.capacity() + range_sums_.capacity())
             * sizeof(double)
         + (aggregate_of_.capacity() + touch_offsets_.capacity() + touch_aggregates_.capacity()
            + slot_touch_.capacity() + coarse_entries_.capacity())
               * sizeof(int)
         + static_cast<std::size_t>(coarse_.nonZeros()) * (sizeof(double) + sizeof(int))
         + 2 * static_cast<std::size_t>(coarse_vector_.size()) * sizeof(double)
         + factor_->memory_bytes();
}

}  // namespace softbench
