// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <chrono>

namespace softbench {

/// Whether a model's step runs its parallel loops on the OpenMP threads or on the calling
/// thread alone, chosen step by step from the wall time each way took. Only for a model whose
/// results do not depend on the thread count (the corotational FEM: every loop's order is fixed
/// by its vertex numbering), where the choice changes the time and nothing else. On an idle
/// 2-core machine two threads win (liver_x16: 1.85x); when another process holds a core they
/// lose, as every parallel region waits for the thread the scheduler has set aside (liver_x16:
/// 2.3x slower than one thread). So each way keeps a running average of its steps' times, the
/// faster runs, and every kProbeInterval steps the other runs once to keep its average current.
class ThreadChoice {
 public:
  static constexpr int kProbeInterval = 16;
  /// The newest step's weight in its way's average: half, so that a probe or two tell a core
  /// that has become busy or free.
  static constexpr double kWeight = 0.5;

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
  std::array<double, 2> average_{};  ///< s a step, [0] one thread, [1] parallel; 0: not yet run
  long long steps_ = 0;              ///< steps asked for (64 bits: a soak never wraps it)
  bool parallel_ = true;             ///< the way of the step being run
};

}  // namespace softbench
