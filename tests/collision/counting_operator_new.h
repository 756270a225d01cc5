// SPDX-License-Identifier: MIT
#pragma once

namespace softbench::test {

/// How many times global operator new (all forms but the aligned ones) has run in this program,
/// which links counting_operator_new.cpp in place of the standard library's.
long allocation_count();

}  // namespace softbench::test
