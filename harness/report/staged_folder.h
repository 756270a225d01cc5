// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>
#include <string>

namespace softbench::harness {

/// A command's output folder that lands as one unit: everything is written into a hidden
/// sibling of the target (".NAME.staging-PID-N"), and commit() puts it in the target's place in
/// one rename (an exchange, when the target exists, then the old folder is removed). A reader
/// sees the old folder or the new one, never metrics.json from one run beside summary.md from
/// another; a run that fails, is interrupted or is killed leaves the old folder as it was.
///
/// The target may exist only as a folder softbench made (it holds the marker file kMarkerFile,
/// or, from before the marker, a command's report: metrics.json, compare.json, stability.json
/// or verify.json) or an empty one: replacing a user's folder given as --out would delete it.
/// Staging folders left by processes that no longer run (killed with SIGKILL, a power cut) are
/// removed when the next command stages beside them.
class StagedFolder {
 public:
  /// The file every staged folder carries, so that the next run may replace it.
  static constexpr const char* kMarkerFile = ".softbench-output";

  /// Checks that `target` may be replaced and creates the staging folder, before any work, so
  /// that a bad --out is found at once. Throws InputError "OPTION TARGET: cannot write (why)".
  StagedFolder(std::filesystem::path target, std::string option);
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  /// Where to write (the staging folder until commit(), the target after).
  const std::filesystem::path& path() const { return committed_ ? target_ : staging_; }
  const std::filesystem::path& target() const { return target_; }

  /// Puts the staged folder at the target. Throws InputError if the file system refuses.
  void commit();
  /// Where a file written under the staging folder is once committed.
  std::filesystem::path landed(const std::filesystem::path& staged_file) const {
    return target_ / staged_file.lexically_relative(staging_);
  }

 private:
  [[noreturn]] void fail(const std::string& why) const;

  std::filesystem::path target_;
  std::string option_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace softbench::harness
