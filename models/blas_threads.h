// SPDX-License-Identifier: MIT
// CHOLMOD's supernodal factorisation spends its time in BLAS, and OpenBLAS splits a kernel's
// sums over as many threads as it is given (OPENBLAS_NUM_THREADS, else OMP_NUM_THREADS, else
// the cores): the same factorisation then differs in its last bits between one and two threads
// (3.5e-12 relative on the liver), and a run is not reproducible across machines or thread
// settings. softbench pins OpenBLAS to one thread before the first factorisation, so a CHOLMOD
// solve gives the same bits at any thread count; the models' own OpenMP loops keep their threads.
// On the liver a supernode is too small for a second BLAS thread to pay; the cost on larger
// meshes is measured in bench/fem_bench.cpp.
#pragma once

namespace softbench {

/// Pins the BLAS that CHOLMOD calls to one thread, once per process; a BLAS other than
/// OpenBLAS (no openblas_set_num_threads) is left as it is. Returns whether it was pinned.
/// SOFTBENCH_BLAS_THREADS=N in the environment leaves OpenBLAS N threads instead (N > 1: faster
/// factorisations of large meshes, results no longer bit-identical across thread counts).
bool pin_blas_threads();

}  // namespace softbench
