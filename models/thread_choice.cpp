// SPDX-License-Identifier: MIT
#include "models/thread_choice.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>

namespace softbench {

int runnable_in_loadavg(const std::string& text) {
  std::istringstream in(text);
  double load = 0.0;
  std::string tasks;
  if (!(in >> load >> load >> load >> tasks)) {
    return -1;
  }
  const std::size_t slash = tasks.find('/');
  if (slash == 0 || slash == std::string::npos) {
    return -1;
  }
  int runnable = 0;
  for (std::size_t k = 0; k < slash; ++k) {
    if (tasks[k] < '0' || tasks[k] > '9' || runnable > 100'000'000) {
      return -1;
    }
    runnable = 10 * runnable + (tasks[k] - '0');
  }
  return runnable;
}

bool runnable_in_stat(const std::string& line) {
  // "id (name) state ...": the name may hold spaces and parentheses; the state follows the
  // last ')'.
  const std::size_t close = line.rfind(')');
  return close != std::string::npos && close + 2 < line.size() && line[close + 1] == ' '
         && line[close + 2] == 'R';
}

namespace {

/// The runnable scheduling entities of the machine now; -1 if that cannot be read (not Linux).
int runnable_on_machine() {
  std::ifstream file("/proc/loadavg");
  std::string text;
  std::getline(file, text);
  return runnable_in_loadavg(text);
}

/// This process's threads that are runnable now: the caller, and OpenMP threads still spinning
/// after a parallel region.
int runnable_in_process() {
  int runnable = 0;
  std::error_code error;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", error)) {
    std::ifstream stat(task.path() / "stat");
    std::string line;
    std::getline(stat, line);
    runnable += runnable_in_stat(line) ? 1 : 0;
  }
  return runnable;
}

}  // namespace

bool core_to_spare() {
  const int machine = runnable_on_machine();
  const auto cores = static_cast<int>(std::thread::hardware_concurrency());
  if (machine < 0 || cores == 0) {
    return true;  // no evidence of a busy core
  }
  // Others' runnable entities beside this process's: they hold all cores but the caller's.
  return machine - runnable_in_process() < cores - 1;
}

ThreadChoice::ThreadChoice(std::function<bool()> cores_free) : cores_free_(std::move(cores_free)) {
  // The OpenMP threads are made at the first parallel region, which took 7 ms beside the
  // shipped liver's 1 ms step: here, not in a step the choice times.
  if (omp_get_max_threads() > 1) {
#pragma omp parallel
    {}
  }
}

bool ThreadChoice::next_parallel() {
  // One thread until the threads have been seen to be faster.
  const bool better_parallel = average_[1] != 0.0 && average_[1] < average_[0];
  if (probe_steps_ == 0 && steps_ >= next_probe_) {
    if (!better_parallel && !cores_free_()) {
      // No core to spare now: a probe of the threads would wait for the scheduler (the shipped
      // liver's step took up to 166 ms so). Counted as a probe that lost.
      interval_ = std::min(2 * interval_, kMaxProbeInterval);
      next_probe_ = steps_ + interval_;
    } else {
      probe_steps_ = kProbeSteps;
      probe_sum_ = 0.0;
      probe_parallel_ = !better_parallel;
    }
  }
  ++steps_;
  parallel_ = probe_steps_ > 0 ? probe_parallel_ : better_parallel;
  return parallel_;
}

void ThreadChoice::record(double seconds) {
  if (steps_ == 1) {
    return;  // the first step also warms the caches up: not a fair sample
  }
  double& average = average_[parallel_ ? 1 : 0];
  if (probe_steps_ == 0) {
    average = average == 0.0 ? seconds : (1.0 - kWeight) * average + kWeight * seconds;
    return;
  }
  probe_sum_ += seconds;
  const int probe_count = kProbeSteps - --probe_steps_;
  const double other = average_[parallel_ ? 0 : 1];
  if (probe_steps_ > 0 && !(seconds > kClearlySlower * other)) {
    return;
  }
  probe_steps_ = 0;
  average = probe_sum_ / probe_count;
  // The next probe: after enough steps of the faster way that what the probe's steps cost more
  // than the faster's is kProbeShare of their time; after a probe that lost, at most twice the
  // last interval (one slow sample, the threads' first region after a pause, say, does not
  // keep the threads away for thousands of steps).
  const double faster = std::min(average, other);
  const double extra = probe_count * std::abs(average - other);
  double steps = faster > 0.0 ? std::ceil(extra / (kProbeShare * faster)) : 0.0;
  if (average > other) {
    steps = std::min(steps, 2.0 * static_cast<double>(interval_));
  }
  interval_ = static_cast<long long>(std::clamp(steps, static_cast<double>(kMinProbeInterval),
                                                static_cast<double>(kMaxProbeInterval)));
  next_probe_ = steps_ + interval_;
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
