// SPDX-License-Identifier: MIT
#include "harness/interrupt.h"

#include <csignal>

namespace softbench::harness {
namespace {

// Lock-free and async-signal-safe: all a handler may touch.
volatile std::sig_atomic_t flag = 0;

extern "C" void raise_flag(int) { flag = 1; }

}  // namespace

void install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = raise_flag;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;  // the second signal takes the default action: end now
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

void request_interrupt() { flag = 1; }
void clear_interrupt() { flag = 0; }
bool interrupt_requested() { return flag != 0; }

void check_interrupted() {
  if (flag != 0) {
    throw Interrupted();
  }
}

}  // namespace softbench::harness
