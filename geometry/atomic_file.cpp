// SPDX-License-Identifier: MIT
#include "geometry/atomic_file.h"

#include "geometry/text_tokenizer.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <fstream>
#include <string>
#include <system_error>

namespace softbench {
namespace {

// Unique per process (pid) and per call (counter), so concurrent writers never share a temporary.
std::filesystem::path temporary_beside(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  return path.parent_path()
         / concat(".", path.filename().string(), ".tmp", ::getpid(), "_", counter++);
}

[[noreturn]] void throw_cannot_write(const std::filesystem::path& path, const std::string& reason) {
  throw_file_error(path.string(), concat("cannot write (", reason, ")"));
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write_content) {
  if (path.filename().empty()) {
    throw_cannot_write(path, "not a file name");
  }
  const std::filesystem::path temporary = temporary_beside(path);
  errno = 0;
  std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
  if (!out) {
    throw_cannot_write(path, std::generic_category().message(errno != 0 ? errno : EIO));
  }
  std::error_code ignored;
  try {
    write_content(out);
    out.close();
  } catch (...) {
    std::filesystem::remove(temporary, ignored);
    throw;
  }
  if (!out) {
    std::filesystem::remove(temporary, ignored);
    throw_cannot_write(path, "I/O error while writing; is the disk full?");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, ignored);
    throw_cannot_write(path, error.message());
  }
}

}  // namespace softbench
