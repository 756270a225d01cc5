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

/// The process's CPU time over all its threads, seconds: for ratios between peers that run in
/// the same process, which a descheduled thread would distort in wall time (13.7x in wall time
/// where CPU time said 10.1x on a loaded machine), while every thread a parallel model uses
/// still counts.
inline double process_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) * 1e-9;
}

}  // namespace softbench::bench
