// SPDX-License-Identifier: MIT
#include "render/image.h"

#include "geometry/atomic_file.h"
#include "geometry/input_error.h"

#include <png.h>

#include <algorithm>
#include <cstring>
#include <string>

namespace softbench::render {
namespace {

/// The largest side read_png accepts (a picture, not a poster).
constexpr png_uint_32 kMaxSide = 16384;

}  // namespace

Image::Image(int columns, int rows, std::uint8_t grey)
    : width(columns),
      height(rows),
      rgba(static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows) * 4, grey) {
  for (std::size_t k = 3; k < rgba.size(); k += 4) {
    rgba[k] = 255;
  }
}

Image downsample(const Image& image, int factor) {
  Image result(image.width / factor, image.height / factor);
  const int samples = factor * factor;
  for (int y = 0; y < result.height; ++y) {
    for (int x = 0; x < result.width; ++x) {
      int sum[4] = {0, 0, 0, 0};
      for (int dy = 0; dy < factor; ++dy) {
        for (int dx = 0; dx < factor; ++dx) {
          const std::uint8_t* p = image.pixel(factor * x + dx, factor * y + dy);
          for (int c = 0; c < 4; ++c) {
            sum[c] += p[c];
          }
        }
      }
      std::uint8_t* out = result.pixel(x, y);
      for (int c = 0; c < 4; ++c) {
        out[c] = static_cast<std::uint8_t>((sum[c] + samples / 2) / samples);
      }
    }
  }
  return result;
}

void paste(const Image& tile, int x, int y, Image& canvas) {
  for (int row = 0; row < tile.height; ++row) {
    const int target_y = y + row;
    if (target_y < 0 || target_y >= canvas.height) {
      continue;
    }
    for (int column = 0; column < tile.width; ++column) {
      const int target_x = x + column;
      if (target_x >= 0 && target_x < canvas.width) {
        std::memcpy(canvas.pixel(target_x, target_y), tile.pixel(column, row), 4);
      }
    }
  }
}

void write_png(const std::filesystem::path& path, const Image& image) {
  // Drop alpha: every picture is opaque.
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(image.width)
                                * static_cast<std::size_t>(image.height) * 3);
  for (std::size_t p = 0, q = 0; p < image.rgba.size(); p += 4, q += 3) {
    std::memcpy(&rgb[q], &image.rgba[p], 3);
  }
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  // First call: the size; second: the bytes.
  if (png_image_write_to_memory(&png, nullptr, &size, 0, rgb.data(), 0, nullptr) == 0) {
    throw InputError(path.string() + ": cannot encode the PNG (" + png.message + ")");
  }
  std::vector<std::uint8_t> bytes(size);
  if (png_image_write_to_memory(&png, bytes.data(), &size, 0, rgb.data(), 0, nullptr) == 0) {
    throw InputError(path.string() + ": cannot encode the PNG (" + png.message + ")");
  }
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(size));
  });
}

Image read_png(const std::filesystem::path& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&png, path.c_str()) == 0) {
    throw InputError(path.string() + ": not a readable PNG (" + png.message + ")");
  }
  if (png.width > kMaxSide || png.height > kMaxSide) {
    png_image_free(&png);
    throw InputError(path.string() + ": " + std::to_string(png.width) + " x "
                     + std::to_string(png.height) + " pixels, over the limit of "
                     + std::to_string(kMaxSide) + " a side");
  }
  png.format = PNG_FORMAT_RGBA;
  Image image(static_cast<int>(png.width), static_cast<int>(png.height));
  if (png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr) == 0) {
    throw InputError(path.string() + ": not a readable PNG (" + png.message + ")");
  }
  return image;
}

}  // namespace softbench::render
