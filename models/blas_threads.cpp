// SPDX-License-Identifier: MIT
#include "models/blas_threads.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <string>

namespace softbench {

bool pin_blas_threads() {
  static std::once_flag once;
  static bool pinned = false;
  std::call_once(once, [] {
    // Looked up at run time: the BLAS is a Debian alternative (OpenBLAS, BLIS, the reference),
    // chosen on the machine, not at link time.
    using SetThreads = void (*)(int);
    auto* set_threads =
        reinterpret_cast<SetThreads>(::dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    if (set_threads == nullptr) {
      return;
    }
    int threads = 1;
    if (const char* given = std::getenv("SOFTBENCH_BLAS_THREADS")) {
      try {
        threads = std::max(1, std::stoi(given));
      } catch (const std::exception&) {
        threads = 1;  // not a number: the reproducible default
      }
    }
    set_threads(threads);
    pinned = threads == 1;
  });
  return pinned;
}

}  // namespace softbench
