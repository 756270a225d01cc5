// SPDX-License-Identifier: MIT
// Where a result came from: the build that made it and the machine it ran on, written into every
// output (metrics.json, compare.json, sweep records, stability reports, benchmark context), and
// the stable content hash that names cached and sharded results.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace softbench::harness {

struct Provenance {
  std::string version;     ///< softbench's version (CMake project version)
  std::string revision;    ///< `git describe --always --dirty` at build time, or "unknown"
  std::string build_type;  ///< CMake build type, e.g. "Release"
  std::string compiler;    ///< compiler and version
  std::string cpu;         ///< "model name" from /proc/cpuinfo, or "unknown CPU"
  int threads = 1;         ///< OpenMP threads a parallel region gets
};

/// This process's provenance.
const Provenance& provenance();
nlohmann::json to_json(const Provenance& provenance);
/// "softbench 0.1.0 (revision abc1234, Release, GCC 12.2.0)": `softbench --version`.
std::string version_line();
/// What identifies the build in cache keys: results from different builds never mix silently.
std::string build_fingerprint();

/// FNV-1a 64 of `text` as 16 hex digits: a name that is the same on every machine.
std::string stable_hash(const std::string& text);
/// stable_hash of a file's bytes; throws InputError naming the file if it cannot be read.
std::string file_hash(const std::string& path);

}  // namespace softbench::harness
