// SPDX-License-Identifier: MIT
// Ctrl-C and SIGTERM (a batch system's time limit) stop a command between two steps, not in the
// middle of writing a file: the handler only raises a flag, every simulation loop checks it once
// a step, and the command ends with one line and status 130, leaving what it had written whole
// (files are written to a temporary and renamed) and nothing half-written.
#pragma once

#include <stdexcept>

namespace softbench::harness {

/// Thrown by check_interrupted() once a stop was asked for.
class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted") {}
};

/// SIGINT and SIGTERM raise the flag; a second signal ends the process at once (the handler is
/// reset after the first), for a loop that does not check.
void install_interrupt_handlers();
/// Raises or lowers the flag by hand (tests; the handlers raise it).
void request_interrupt();
void clear_interrupt();
bool interrupt_requested();
/// Throws Interrupted if the flag is up: call it between steps.
void check_interrupted();

}  // namespace softbench::harness
