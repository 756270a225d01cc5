// SPDX-License-Identifier: MIT
#pragma once

#include <ctime>

namespace softbench::bench {

/// The calling thread's CPU time, microseconds. Benchmarks that time parts of an iteration, or
/// interleave peers, read it rather than wall time: on a shared machine wall time includes time
/// the thread was descheduled. A call costs about 0.2 us.
inline double thread_cpu_us() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e6 + static_cast<double>(now.tv_nsec) * 1e-3;
}

}  // namespace softbench::bench
