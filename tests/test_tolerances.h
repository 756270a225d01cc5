// SPDX-License-Identifier: MIT
#pragma once

// Named tolerances, each with the reason for its value (MuJoCo's MjTol idea).
namespace softbench::test {

/// Sums of a few dozen double products of O(1) numbers: a handful of ulps each.
inline constexpr double kRoundoff = 1e-12;
/// Values that went through a text file written with 17 significant digits: exact in principle,
/// but leave room for parsers that round the last digit.
inline constexpr double kTextRoundTrip = 1e-14;
/// Values that went through float32 (binary STL, VTK float): 2^-24 relative.
inline constexpr double kFloat32 = 1e-6;

}  // namespace softbench::test
