// SPDX-License-Identifier: MIT
// A per-step series whose memory stays flat however long the run: a scene may ask for
// 10,000,000 steps, and one value a step for each of a run's series would then hold hundreds of
// megabytes and write a metrics.json of gigabytes. Up to `capacity` values every step is kept
// (every shipped scene is far below it); past that the series thins itself to every second kept
// value, then every fourth, and so on, so it always spans the whole run at an even stride.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace softbench::harness {

/// Values offered one a step, kept at a stride that doubles whenever `capacity` is reached.
/// `Keep(a, b)` chooses which of two neighbours survives a thinning (by default the earlier,
/// an even subsample); a series whose peaks matter keeps the larger.
template <typename T>
class DecimatedSeries {
 public:
  explicit DecimatedSeries(std::size_t capacity) : capacity_(capacity < 2 ? 2 : capacity) {}

  /// Offers the next step's value; it is kept when its step falls on the stride. With a
  /// `better` predicate, a value off the stride replaces the last kept one when better(value,
  /// last) holds, so a peak between two kept steps is not lost.
  template <typename Better>
  void offer(const T& value, Better better) {
    if (offered_ % stride_ == 0) {
      if (values_.size() == capacity_) {
        thin(better);
      }
      if (offered_ % stride_ == 0) {
        values_.push_back(value);
      } else if (better(value, values_.back())) {
        values_.back() = value;
      }
    } else if (better(value, values_.back())) {
      values_.back() = value;
    }
    ++offered_;
  }
  void offer(const T& value) {
    offer(value, [](const T&, const T&) { return false; });
  }

  /// Takes the memory of `capacity` values now, so that offering never allocates (a soak
  /// measures the heap the run holds, which a growing series would move).
  void reserve_capacity() { values_.reserve(capacity_); }

  const std::vector<T>& values() const { return values_; }
  std::vector<T> take() && { return std::move(values_); }
  std::size_t offered() const { return offered_; }
  std::size_t stride() const { return stride_; }
  std::size_t capacity() const { return capacity_; }

 private:
  template <typename Better>
  void thin(Better better) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < values_.size(); i += 2) {
      const bool take_second = i + 1 < values_.size() && better(values_[i + 1], values_[i]);
      values_[kept++] = values_[take_second ? i + 1 : i];
    }
    values_.resize(kept);
    stride_ *= 2;
  }

  std::size_t capacity_;
  std::size_t stride_ = 1;
  std::size_t offered_ = 0;
  std::vector<T> values_;
};

}  // namespace softbench::harness
