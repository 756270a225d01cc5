// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <chrono>
#include <functional>
#include <string>

namespace softbench {

/// Whether a thread started now would find a core: fewer entities of other processes are
/// runnable now (Linux's /proc/loadavg less this process's runnable threads) than the machine
/// has cores besides the caller's. True where that cannot be read.
bool core_to_spare();
/// The runnable count in /proc/loadavg's text ("0.70 1.01 1.54 1/79 7400": 1); -1 if malformed.
int runnable_in_loadavg(const std::string& text);
/// Whether a line of /proc/<pid>/task/<id>/stat says its task is runnable (state R).
bool runnable_in_stat(const std::string& line);

/// Whether a model's step runs its parallel loops on the OpenMP threads or on the calling
/// thread alone, chosen step by step from the wall time each way took. Only for a model whose
/// results do not depend on the thread count (the corotational FEM: every loop's order is fixed
/// by its vertex numbering), where the choice changes the time and nothing else. On an idle
/// 2-core machine two threads win (liver_x16: 1.85x; the shipped liver: 1.5x); when another
/// process holds a core they lose, as every parallel region waits for the thread the scheduler
/// has set aside (liver_x16: 2.3x slower than one thread; a step of the shipped liver took 2-60
/// times its time, once 166 ms).
///
/// So the faster way runs, by a running average of each way's step times, and now and then the
/// other runs for kProbeSteps steps (a probe), whose mean is that way's average from then on
/// (it has not run since its last probe: what it took then says nothing of now). A probe step
/// kClearlySlower than the other way's average ends the probe at once. The probes are spaced by
/// what they cost: the next comes once the faster way's steps since have taken 1/kProbeShare
/// times the probe's extra time, within kMinProbeInterval and kMaxProbeInterval steps, and after
/// a probe that lost no later than twice the last interval (one slow sample does not keep the
/// threads away for thousands of steps). On the idle 2-core machine one thread is tried every
/// ~250 steps of the shipped liver. The threads are probed only while a core is free for them
/// (core_to_spare()): with a core busy, none of the shipped liver's steps ran on them, where
/// without that test a run of 300 steps spent 10-20 probe steps of 2-166 ms on them. A probe
/// skipped so counts as one that lost.
///
/// The first two steps run on one thread (the first, which warms the caches up, is not
/// counted); the threads are probed from the third.
class ThreadChoice {
 public:
  /// Steps a probe runs the other way: their mean is that way's average from then on. A step
  /// that takes kClearlySlower times the other way's average ends the probe at once.
  static constexpr int kProbeSteps = 4;
  static constexpr double kClearlySlower = 2.0;
  static constexpr long long kMinProbeInterval = 16;
  static constexpr long long kMaxProbeInterval = 4096;
  static constexpr double kProbeShare = 0.01;
  /// The newest step's weight in its way's average. A step on the threads takes 50-100 times
  /// longer once a core is busy, so one step turns the choice even at an eighth; a step that
  /// the scheduler or the contact made a few times longer does not.
  static constexpr double kWeight = 0.125;

  /// Starts the OpenMP threads (their first region is slow: not in a step that is timed).
  /// `cores_free()` says whether a core is free for the threads now; the threads are probed
  /// only then (by default core_to_spare()).
  explicit ThreadChoice(std::function<bool()> cores_free = core_to_spare);

  /// Whether the next step may use the OpenMP threads (false: one thread).
  bool next_parallel();
  /// The wall time (s) of the step next_parallel() was asked for.
  void record(double seconds);

  /// A step run the chosen way: one thread for it if so chosen (omp_set_num_threads, restored
  /// after), its wall time recorded when the scope ends.
  class Scope {
   public:
    explicit Scope(ThreadChoice& choice);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    ThreadChoice& choice_;
    int threads_before_ = 0;
    std::chrono::steady_clock::time_point start_;
  };

 private:
  std::function<bool()> cores_free_;
  std::array<double, 2> average_{};  ///< s a step, [0] one thread, [1] parallel; 0: not yet run
  long long steps_ = 0;              ///< steps asked for (64 bits: a soak never wraps it)
  long long next_probe_ = 2;         ///< the step (counted from 0) the next probe starts at
  long long interval_ = kMinProbeInterval / 2;  ///< steps from the last probe to the next
  int probe_steps_ = 0;                         ///< steps left in the probe under way (0: none)
  double probe_sum_ = 0.0;                      ///< s: the probe's steps so far
  bool probe_parallel_ = false;                 ///< the way the probe runs
  bool parallel_ = false;                       ///< the way of the step being run
};

}  // namespace softbench
