// SPDX-License-Identifier: MIT
#include "fuzz/fuzz_support.h"

#include "geometry/input_error.h"
#include "geometry/mesh_validation.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <system_error>
#include <typeinfo>

namespace softbench::fuzz {
namespace {

namespace fs = std::filesystem;

void remove_scratch_folder() {
  std::error_code ignored;
  fs::remove_all(scratch_folder(), ignored);
}

template <int Rows>
void check_indices(const MeshData& mesh, const Eigen::Matrix<int, Rows, Eigen::Dynamic>& cells,
                   const char* kind) {
  const Eigen::Index vertices = mesh.vertices.cols();
  for (Eigen::Index c = 0; c < cells.cols(); ++c) {
    for (Eigen::Index corner = 0; corner < Rows; ++corner) {
      if (cells(corner, c) < 0 || cells(corner, c) >= vertices) {
        finding(std::string(kind) + " " + std::to_string(c) + " has vertex index "
                + std::to_string(cells(corner, c)) + ", out of range for "
                + std::to_string(vertices) + " vertices (the reader should have refused it)");
      }
    }
  }
}

}  // namespace

std::string as_text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

const fs::path& scratch_folder() {
  static const fs::path folder = [] {
    // Memory-backed where there is /dev/shm: a file is written for every input.
    const char* tmp = std::getenv("TMPDIR");
    std::error_code error;
    const fs::path base = tmp != nullptr && *tmp != '\0'           ? fs::path(tmp)
                          : fs::is_directory("/dev/shm", error) ? fs::path("/dev/shm")
                                                                 : fs::path("/tmp");
    fs::path made = base / ("softbench-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(made);
    return made;
  }();
  static const bool cleaned_at_exit = std::atexit(remove_scratch_folder) == 0;
  static_cast<void>(cleaned_at_exit);
  return folder;
}

fs::path write_scratch_file(const std::string& name, std::string_view bytes) {
  const fs::path path = scratch_folder() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out.flush()) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

void remove_scratch_file(const std::string& name) {
  std::error_code ignored;
  fs::remove(scratch_folder() / name, ignored);
}

void finding(std::string_view what) {
  std::fprintf(stderr, "fuzz finding: %.*s\n", static_cast<int>(what.size()), what.data());
  std::abort();
}

void expect_only_input_errors(const std::string& source, const std::function<void()>& body) {
  try {
    body();
  } catch (const InputError& error) {
    const std::string_view message = error.what();
    if (message.find_first_of("\n\r") != std::string_view::npos) {
      finding("InputError of more than one line: " + std::string(message));
    }
    if (!message.starts_with(source)) {
      finding("InputError not naming " + source + " first: " + std::string(message));
    }
  } catch (const std::exception& error) {
    finding(std::string("unexpected ") + typeid(error).name() + ": " + error.what());
  }
}

void read_and_check_mesh(const std::string& source, const std::function<MeshData()>& read) {
  MeshData mesh;
  bool read_whole = false;
  expect_only_input_errors(source, [&] {
    mesh = read();
    read_whole = true;
  });
  if (!read_whole) {
    return;
  }
  if (!mesh.vertices.allFinite()) {
    finding("a vertex has a non-finite coordinate (the reader should have refused it)");
  }
  check_indices(mesh, mesh.triangles, "triangle");
  check_indices(mesh, mesh.tetrahedra, "tet");
  if (mesh.tetrahedra.cols() > 0) {
    expect_only_input_errors(source, [&] { make_tet_mesh(mesh); });
  }
  if (mesh.triangles.cols() > 0) {
    expect_only_input_errors(source, [&] { make_closed_surface(mesh); });
  }
}

void fuzz_mesh_reader(std::string_view bytes,
                      const std::string& extension,
                      const std::function<MeshData(const fs::path&)>& reader) {
  const fs::path path = write_scratch_file("input" + extension, bytes);
  read_and_check_mesh(path.string(), [&] { return reader(path); });
}

}  // namespace softbench::fuzz
