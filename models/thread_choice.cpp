// SPDX-License-Identifier: MIT
#include "models/thread_choice.h"

#include <omp.h>

namespace softbench {

bool ThreadChoice::next_parallel() {
  // Parallel until one thread has been seen to be faster; the first probe of one thread comes
  // at the third step (after a parallel one that counts), so a busy core is found at once.
  const bool better_parallel = average_[0] == 0.0 || average_[1] <= average_[0];
  const bool probe = steps_ % kProbeInterval == 2;
  ++steps_;
  parallel_ = probe ? !better_parallel : better_parallel;
  return parallel_;
}

void ThreadChoice::record(double seconds) {
  if (steps_ == 1) {
    return;  // the first step also warms the caches and the threads up: not a fair sample
  }
  double& average = average_[parallel_ ? 1 : 0];
  average = average == 0.0 ? seconds : (1.0 - kWeight) * average + kWeight * seconds;
}

ThreadChoice::Scope::Scope(ThreadChoice& choice)
    : choice_(choice), threads_before_(omp_get_max_threads()) {
  if (!choice_.next_parallel()) {
    omp_set_num_threads(1);
  }
  start_ = std::chrono::steady_clock::now();
}

ThreadChoice::Scope::~Scope() {
  choice_.record(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  omp_set_num_threads(threads_before_);
}

}  // namespace softbench
