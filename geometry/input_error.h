// SPDX-License-Identifier: MIT
#pragma once

#include <stdexcept>
#include <string>

namespace softbench {

/// Bad input from a user: a file, a mesh, a scene key, a parameter. The message is one line a
/// person can act on: where (file, line, element or key), what was expected, what was found.
/// The CLI catches it, prints it and exits with status 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace softbench
