// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/input_error.h"

#include <gmock/gmock.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <string_view>

// Helpers shared by the mesh file tests: expected-error matchers and byte builders for binary
// files made inside the tests.
namespace softbench::test {

/// Matches a callable that throws InputError with exactly `text` as its message, after the
/// folder of the file it names: `text` starts with the file's name ("cut.vtk: line 6: ...") and
/// the message is "<folder>/" + text, the folder being the test's own temporary one. Each
/// reader's test file holds its bad-input catalogue so: one test a malformed input, with the
/// whole message a user sees.
MATCHER_P(IsMessageInAFolder, text, "is <folder>/" + std::string(text)) {
  const std::string_view message = arg;
  const std::string_view tail = text;
  if (message.size() <= tail.size() || !message.ends_with(tail)) {
    return false;
  }
  // Only a folder before it: no second message, no line break.
  const std::string_view folder = message.substr(0, message.size() - tail.size());
  return folder.ends_with('/') && folder.find(": ") == std::string_view::npos
         && folder.find('\n') == std::string_view::npos;
}

inline auto ThrowsInputError(const std::string& text) {
  return testing::ThrowsMessage<InputError>(IsMessageInAFolder(text));
}

/// `count` bytes from a seeded generator: the same garbage on every run.
inline std::string random_bytes(unsigned seed, std::size_t count) {
  std::mt19937 generator(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  std::string bytes(count, '\0');
  for (char& c : bytes) {
    c = static_cast<char>(byte(generator));
  }
  return bytes;
}

/// Appends numbers to a byte string in a fixed byte order (binary STL: little, VTK: big).
class ByteWriter {
 public:
  explicit ByteWriter(std::endian order) : order_(order) {}
  template <typename T>
  ByteWriter& put(T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (order_ != std::endian::native) {
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) {
        std::swap(raw[i], raw[sizeof(T) - 1 - i]);
      }
    }
    bytes_.append(raw, sizeof(T));
    return *this;
  }
  ByteWriter& text(const std::string& text) {
    bytes_ += text;
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::endian order_;
  std::string bytes_;
};

}  // namespace softbench::test
