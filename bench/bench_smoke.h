// SPDX-License-Identifier: MIT
#pragma once

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string_view>

// A smoke run (SOFTBENCH_BENCH_SMOKE=1, as ctest's BenchSmoke.* tests set it) runs every
// benchmark once, briefly, so that none can rot without a test failing. Google Benchmark lets
// what a benchmark fixes in code (its minimum time, its repetitions) override the command line,
// so the benchmarks that fix them ask here first.
namespace softbench::bench {

inline bool smoke_run() {
  const char* value = std::getenv("SOFTBENCH_BENCH_SMOKE");
  return value != nullptr && std::string_view(value) != "" && std::string_view(value) != "0";
}

/// `full` in a real run, `smoke` in a smoke run: the steps of a warm-up, of an accuracy check
/// beside the timing, of a stability run, which in a smoke run need only run.
template <class T>
T unless_smoke(T full, T smoke) {
  return smoke_run() ? smoke : full;
}

/// `repetitions` (and `min_time` seconds, if positive) for `benchmark`, except in a smoke run.
/// Every repetition stays in the JSON output, so two runs can be compared with a rank test;
/// the console shows their aggregates.
inline benchmark::internal::Benchmark* repeated(benchmark::internal::Benchmark* benchmark,
                                                int repetitions,
                                                double min_time = 0.0) {
  if (smoke_run()) {
    return benchmark;
  }
  if (min_time > 0.0) {
    benchmark->MinTime(min_time);
  }
  return benchmark->Repetitions(repetitions)->DisplayAggregatesOnly(true);
}

}  // namespace softbench::bench
