// SPDX-License-Identifier: MIT
#include "harness/provenance.h"

#include "geometry/input_error.h"
#include "harness/build_revision.h"

#include <omp.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace softbench::harness {
namespace {

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos && colon + 2 <= line.size()) {
        return line.substr(colon + 2);
      }
    }
  }
  return "unknown CPU";
}

std::string compiler() {
#if defined(__clang__)
  return std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("GCC ") + __VERSION__;
#else
  return "unknown compiler";
#endif
}

std::uint64_t fnv1a(std::uint64_t hash, const char* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= static_cast<unsigned char>(data[i]);
    hash *= 1099511628211ULL;
  }
  return hash;
}

constexpr std::uint64_t kFnvOffset = 14695981039346656037ULL;

std::string hex(std::uint64_t hash) {
  char digits[17];
  std::snprintf(digits, sizeof digits, "%016llx", static_cast<unsigned long long>(hash));
  return digits;
}

}  // namespace

const Provenance& provenance() {
  static const Provenance value{SOFTBENCH_VERSION, kBuildRevision, SOFTBENCH_BUILD_TYPE,
                                compiler(),        cpu_model(),    omp_get_max_threads()};
  return value;
}

nlohmann::json to_json(const Provenance& p) {
  return {{"version", p.version},   {"revision", p.revision}, {"build_type", p.build_type},
          {"compiler", p.compiler}, {"cpu", p.cpu},           {"threads", p.threads}};
}

std::string version_line() {
  const Provenance& p = provenance();
  return "softbench " + p.version + " (revision " + p.revision + ", " + p.build_type + ", "
         + p.compiler + ")";
}

std::string build_fingerprint() {
  const Provenance& p = provenance();
  return p.version + " " + p.revision + " " + p.build_type + " " + p.compiler;
}

std::string stable_hash(const std::string& text) {
  return hex(fnv1a(kFnvOffset, text.data(), text.size()));
}

std::string file_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(path + ": cannot open");
  }
  std::uint64_t hash = kFnvOffset;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    hash = fnv1a(hash, buffer, static_cast<std::size_t>(in.gcount()));
  }
  return hex(hash);
}

}  // namespace softbench::harness
