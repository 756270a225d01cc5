// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

// What the libFuzzer targets share. The project's rule for bad input is one InputError whose
// message is one line naming the file (then the line, element or JSON pointer): a target runs
// its reader under expect_only_input_errors(), which lets that through and turns anything else
// (another exception, a message of several lines or one not naming the file) into a finding.
// Crashes, sanitizer reports, timeouts and runaway allocations are libFuzzer's to catch.
namespace softbench::fuzz {

/// The fuzzer's input as text (bytes as they are).
std::string as_text(const std::uint8_t* data, std::size_t size);

/// This process's own folder for input files (under $TMPDIR, else /dev/shm, else /tmp), made
/// on first use and removed at exit.
const std::filesystem::path& scratch_folder();
/// Writes `bytes` to scratch_folder() / name, replacing it; returns the path.
std::filesystem::path write_scratch_file(const std::string& name, std::string_view bytes);
/// Removes scratch_folder() / name if it is there.
void remove_scratch_file(const std::string& name);

/// Prints "fuzz finding: <what>" and aborts, so libFuzzer keeps the input.
[[noreturn]] void finding(std::string_view what);

/// Runs `body`. An InputError is the expected end of bad input, if its message is one line that
/// starts with `source` (the file named); anything else thrown is a finding.
void expect_only_input_errors(const std::string& source, const std::function<void()>& body);

/// One mesh read: `read` runs under expect_only_input_errors(source); what it returns must
/// have every index in range (the readers' promise: a finding if not), then is validated as the
/// commands use it: as a tet mesh when it has tets, as a closed surface when it has triangles
/// (each may throw InputError for bad geometry, which must name the file too).
void read_and_check_mesh(const std::string& source, const std::function<MeshData()>& read);

/// read_and_check_mesh() of `bytes` written to the scratch file "input<extension>" and read by
/// `reader`.
void fuzz_mesh_reader(std::string_view bytes,
                      const std::string& extension,
                      const std::function<MeshData(const std::filesystem::path&)>& reader);

}  // namespace softbench::fuzz
