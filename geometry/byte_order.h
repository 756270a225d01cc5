// SPDX-License-Identifier: MIT
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace softbench {

/// A number stored in `sizeof(T)` bytes at `bytes` in the given byte order, whatever the host's
/// (binary STL is little-endian, legacy VTK big-endian). `bytes` need not be aligned.
template <typename T>
T load_number(const char* bytes, std::endian order) {
  static_assert(std::is_arithmetic_v<T>);
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, bytes, sizeof(T));
  if (order != std::endian::native) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) {
      const unsigned char swapped = raw[i];
      raw[i] = raw[sizeof(T) - 1 - i];
      raw[sizeof(T) - 1 - i] = swapped;
    }
  }
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

}  // namespace softbench
