// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace softbench::render {

/// 8-bit RGBA pixels, rows from the top.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  ///< width * height * 4

  Image() = default;
  Image(int columns, int rows, std::uint8_t grey = 255);
  const std::uint8_t* pixel(int x, int y) const {
    return rgba.data() + 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width)
                              + static_cast<std::size_t>(x));
  }
  std::uint8_t* pixel(int x, int y) {
    return rgba.data() + 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width)
                              + static_cast<std::size_t>(x));
  }
};

/// The mean of each factor x factor block (anti-aliasing by supersampling).
Image downsample(const Image& image, int factor);
/// Copies `tile` into `canvas` with its top-left corner at (x, y) (clipped).
void paste(const Image& tile, int x, int y, Image& canvas);

/// Writes `image` as an 8-bit RGB PNG (libpng), atomically (write_file_atomically). Throws
/// InputError naming the file when it cannot be written.
void write_png(const std::filesystem::path& path, const Image& image);
/// Reads an 8-bit RGB or RGBA PNG (for tests and checks). Throws InputError naming the file.
Image read_png(const std::filesystem::path& path);

}  // namespace softbench::render
