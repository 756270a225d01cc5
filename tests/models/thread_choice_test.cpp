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

/// A choice that sees a core free (or busy) whatever the machine is doing.
ThreadChoice with_core_free(const bool& free) {
  return ThreadChoice([&free] { return free; });
}

TEST(ThreadChoice, RunsTheFasterWayAndSpacesItsProbesByWhatTheyCost) {
  // The threads twice as fast. Steps 0 and 1 on one thread, the threads' probe at steps 2-5;
  // its four steps saved 1 s each, so one thread's probe comes after 4 / kProbeShare = 400 steps
  // on the threads: steps 406-409, then 810-813.
  ASSERT_EQ(ThreadChoice::kProbeSteps, 4);
  ASSERT_DOUBLE_EQ(ThreadChoice::kProbeShare, 0.01);
  const bool free = true;
  ThreadChoice choice = with_core_free(free);
  EXPECT_EQ(run(choice, 900, 1.0, 2.0), 900 - 2 - 4 - 4);
}

TEST(ThreadChoice, EndsAProbeAtAStepClearlySlowerAndBacksOffAfterEachLoss) {
  // The threads five times slower: each probe of them ends after its first step, and the next
  // comes at most twice the last interval later (16, 32, 64, 128): steps 2, 19, 52, 117, 246.
  const bool free = true;
  ThreadChoice choice = with_core_free(free);
  EXPECT_EQ(run(choice, 246, 10.0, 2.0), 4);
  EXPECT_EQ(run(choice, 1, 10.0, 2.0), 1);
}

TEST(ThreadChoice, TurnsToOneThreadWhenACoreIsBusyAndBackWhenItIsFree) {
  bool free = true;
  ThreadChoice choice = with_core_free(free);
  EXPECT_EQ(run(choice, 300, 1.0, 2.0), 300 - 2);  // the threads from step 2 on
  // Another process takes a core: a step on the threads takes 100 times one thread's. The
  // first (step 300) turns the choice. The threads' probes, due at 406 and then twice as far
  // each time (1206, 2806), are skipped while the core is busy.
  free = false;
  EXPECT_EQ(run(choice, 1000, 200.0, 2.0), 1);
  // The core is free again: the probe at 2806 finds it, and the threads run from then on but
  // for one thread's probe 400 steps after theirs (3210-3213).
  free = true;
  EXPECT_EQ(run(choice, 2000, 1.0, 2.0), (3300 - 2806) - 4);
}

TEST(CoreToSpare, ReadsTheRunnableCountsOfTheMachineAndOfEachThread) {
  EXPECT_EQ(runnable_in_loadavg("0.70 1.01 1.54 1/79 7400\n"), 1);
  EXPECT_EQ(runnable_in_loadavg("2.00 1.50 1.20 12/345 999"), 12);
  EXPECT_EQ(runnable_in_loadavg("0.70 1.01 1.54 79 7400"), -1);
  EXPECT_EQ(runnable_in_loadavg("0.70 1.01"), -1);
  EXPECT_EQ(runnable_in_loadavg("0.70 1.01 1.54 x/79 7400"), -1);
  EXPECT_EQ(runnable_in_loadavg(""), -1);
  EXPECT_TRUE(runnable_in_stat("4242 (softbench) R 1 4242 4242 0 -1"));
  EXPECT_FALSE(runnable_in_stat("4243 (softbench) S 1 4242 4242 0 -1"));
  // A thread's name may hold spaces and parentheses: the state follows the last ')'.
  EXPECT_TRUE(runnable_in_stat("4244 (a (b) c) R 1"));
  EXPECT_FALSE(runnable_in_stat("4245 (R) S 1"));
  EXPECT_FALSE(runnable_in_stat(""));
}

TEST(ThreadChoice, AScopeRunsItsStepOnOneThreadWhenSoChosenAndRestoresTheCount) {
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(2);
  const bool free = true;
  ThreadChoice choice = with_core_free(free);
  run(choice, 3, 6.0, 2.0);  // the threads' probe at the third step finds them slower
  {
    const ThreadChoice::Scope scope(choice);
    EXPECT_EQ(omp_get_max_threads(), 1);
  }
  EXPECT_EQ(omp_get_max_threads(), 2);
  omp_set_num_threads(threads_before);
}

}  // namespace
}  // namespace softbench
