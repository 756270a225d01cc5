// SPDX-License-Identifier: MIT
#pragma once

namespace softbench {

/// body(i) for every i in [0, count). When `shared`, the loop is split among the threads of the
/// enclosing OpenMP parallel region (dynamic, one index at a time: whichever thread is free
/// takes the next, so a thread the scheduler holds back does not hold back a fixed share), with
/// the barrier at its end; otherwise a plain loop on the calling thread, outside any region.
/// (A region of one thread still pays the schedule's bookkeeping per index: 3% of shape
/// matching's step on the liver.)
template <typename Body>
void team_loop(bool shared, int count, const Body& body) {
  if (!shared) {
    for (int i = 0; i < count; ++i) {
      body(i);
    }
    return;
  }
#pragma omp for schedule(dynamic, 1)
  for (int i = 0; i < count; ++i) {
    body(i);
  }
}

/// body(first, last) for consecutive blocks [first, last) of `block` indices covering [0, count)
/// (the last one shorter), split as team_loop() splits its indices.
template <typename Body>
void team_blocks(bool shared, int count, int block, const Body& body) {
  team_loop(shared, (count + block - 1) / block, [&](int b) {
    const int first = b * block;
    body(first, count - first < block ? count : first + block);
  });
}

/// run() inside an OpenMP parallel region when `parallel` (its team_loop(true, ...) calls then
/// split their loops), else on the calling thread alone.
template <typename Run>
void maybe_parallel(bool parallel, const Run& run) {
  if (!parallel) {
    run();
    return;
  }
#pragma omp parallel
  run();
}

}  // namespace softbench
