// SPDX-License-Identifier: MIT
#include "models/thread_choice.h"

#include <gtest/gtest.h>
#include <omp.h>

namespace softbench {
namespace {

/// Runs `steps` steps of `choice`, each taking `parallel_seconds` on the threads and
/// `serial_seconds` on one; returns how many ran on the threads.
int run(ThreadChoice& choice, int steps, double parallel_seconds, double serial_seconds) {
  int parallel = 0;
  for (int step = 0; step < steps; ++step) {
    const bool threads = choice.next_parallel();
    parallel += threads ? 1 : 0;
    choice.record(threads ? parallel_seconds : serial_seconds);
  }
  return parallel;
}

TEST(ThreadChoice, RunsTheFasterWayAndTriesTheOtherOnceAnInterval) {
  ThreadChoice choice;
  constexpr int kSteps = 4 * ThreadChoice::kProbeInterval;
  // The threads twice as fast: one step in an interval on one thread, the probe.
  EXPECT_EQ(run(choice, kSteps, 1.0, 2.0), kSteps - 4);
}

TEST(ThreadChoice, TurnsToOneThreadWhenTheThreadsWaitAndBackWhenTheyNoLongerDo) {
  ThreadChoice choice;
  run(choice, 2, 1.0, 2.0);  // the warm-up, then a step on the threads
  // Another process takes a core: the threads' steps take three times one thread's. The probe
  // of one thread at the third step finds it; the step after it still goes by the threads'
  // older average, and from then on only the probes use the threads.
  constexpr int kSteps = 4 * ThreadChoice::kProbeInterval;
  EXPECT_EQ(run(choice, kSteps, 6.0, 2.0), 4);
  // The core is free again: the threads' probes pull their average down, and within two
  // intervals the threads are chosen again.
  const int parallel = run(choice, 4 * ThreadChoice::kProbeInterval, 1.0, 2.0);
  EXPECT_GE(parallel, 2 * ThreadChoice::kProbeInterval);
  EXPECT_GE(run(choice, ThreadChoice::kProbeInterval, 1.0, 2.0), ThreadChoice::kProbeInterval - 1);
}

TEST(ThreadChoice, AScopeRunsItsStepOnOneThreadWhenSoChosenAndRestoresTheCount) {
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(2);
  ThreadChoice choice;
  run(choice, 3, 6.0, 2.0);  // one thread found faster at the third step
  {
    const ThreadChoice::Scope scope(choice);
    EXPECT_EQ(omp_get_max_threads(), 1);
  }
  EXPECT_EQ(omp_get_max_threads(), 2);
  omp_set_num_threads(threads_before);
}

}  // namespace
}  // namespace softbench
