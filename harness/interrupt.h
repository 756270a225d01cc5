// SPDX-License-Identifier: MIT
// Ctrl-C and SIGTERM (a batch system's time limit) stop a command between two steps, not in the
// middle of writing a file: the handler only raises a flag, every simulation loop checks it once
// a step, and the command ends with one line and status 130. `softbench run` writes what it
// measured up to the stop, and `softbench soak` what its whole cycles measured, marked
// interrupted; a command that compares or fits runs writes nothing of the unfinished work. Output folders land whole or not at all (StagedFolder).
#pragma once

#include <stdexcept>
#include <string>

namespace softbench::harness {

/// Thrown by check_interrupted() once a stop was asked for.
class Interrupted : public std::runtime_error {
 public:
  /// `what`: what became of the command's results, for the one line the command ends with.
  explicit Interrupted(const std::string& what =
                           "stopped between two steps; the unfinished results were not written")
      : std::runtime_error(what) {}
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
