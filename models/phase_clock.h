// SPDX-License-Identifier: MIT
#pragma once

#include <chrono>

namespace softbench {

/// Adds the wall time since the previous lap to one phase of a model's per-phase times (`Times`:
/// a struct of doubles in seconds, as the benchmarks read them); a no-op when there is none, so
/// a step that is not profiled pays nothing but a null check.
template <class Times>
class PhaseClock {
 public:
  explicit PhaseClock(Times* times) : times_(times) {
    if (times_ != nullptr) {
      since_ = std::chrono::steady_clock::now();
    }
  }
  void lap(double Times::*phase) {
    if (times_ != nullptr) {
      const auto now = std::chrono::steady_clock::now();
      times_->*phase += std::chrono::duration<double>(now - since_).count();
      since_ = now;
    }
  }

 private:
  Times* times_;
  std::chrono::steady_clock::time_point since_;
};

}  // namespace softbench
