// SPDX-License-Identifier: MIT
#include "harness/report/staged_folder.h"

#include "geometry/input_error.h"

#include <fcntl.h>  // AT_FDCWD
#include <signal.h>
#include <stdio.h>  // renameat2, RENAME_EXCHANGE (glibc >= 2.28)
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <fstream>
#include <system_error>
#include <utility>

namespace softbench::harness {
namespace fs = std::filesystem;

namespace {

constexpr const char* kStagingTag = ".staging-";

/// Whether process `pid` still runs (kill with signal 0 checks without signalling; EPERM: it
/// runs as another user).
bool process_runs(long pid) {
  return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
}

/// The pid in a staging folder's name ".NAME.staging-PID-N", or 0.
long staging_pid(const std::string& file_name, const std::string& prefix) {
  if (file_name.rfind(prefix, 0) != 0) {
    return 0;
  }
  const char* begin = file_name.data() + prefix.size();
  const char* end = file_name.data() + file_name.size();
  long pid = 0;
  const auto [stop, error] = std::from_chars(begin, end, pid);
  return error == std::errc() && stop != begin && stop != end && *stop == '-' ? pid : 0;
}

/// Whether `folder` is one softbench wrote: it carries the marker, or (written before there
/// was one) a command's report.
bool made_by_softbench(const fs::path& folder) {
  std::error_code error;
  for (const char* file : {StagedFolder::kMarkerFile, "metrics.json", "compare.json",
                           "stability.json", "verify.json"}) {
    if (fs::exists(folder / file, error)) {
      return true;
    }
  }
  return false;
}

}  // namespace

StagedFolder::StagedFolder(fs::path target, std::string option)
    : target_(std::move(target)), option_(std::move(option)) {
  fs::path normal = target_.lexically_normal();
  if (!normal.empty() && !normal.has_filename()) {
    normal = normal.parent_path();  // "out/run/" -> "out/run"
  }
  const std::string name = normal.filename().string();
  if (name.empty() || name == "." || name == "..") {
    fail("not a folder name: give a folder to create or replace, e.g. out/run");
  }
  const fs::path parent = normal.has_parent_path() ? normal.parent_path() : fs::path(".");
  std::error_code error;
  fs::create_directories(parent, error);
  if (!fs::is_directory(parent, error)) {
    fail(parent.string() + " is not a folder");
  }
  if (fs::exists(normal, error)) {
    if (!fs::is_directory(normal, error)) {
      fail("it is a file, not a folder");
    }
    if (!fs::is_empty(normal, error) && !made_by_softbench(normal)) {
      fail("a folder softbench did not make; give a new or an empty folder");
    }
  }

  // What killed processes left beside it.
  const std::string prefix = "." + name + kStagingTag;
  for (const fs::directory_entry& entry : fs::directory_iterator(parent, error)) {
    const long pid = staging_pid(entry.path().filename().string(), prefix);
    if (pid != 0 && !process_runs(pid)) {
      fs::remove_all(entry.path(), error);
    }
  }

  static std::atomic<unsigned> counter{0};
  staging_ =
      parent
      / (prefix + std::to_string(static_cast<long>(::getpid())) + "-" + std::to_string(counter++));
  fs::remove_all(staging_, error);
  if (!fs::create_directory(staging_, error)) {
    fail("no permission to create folders in " + parent.string());
  }
  std::ofstream marker(staging_ / kMarkerFile);
  marker << "A softbench output folder: the next command writing here replaces it whole.\n";
  if (!marker) {
    fs::remove_all(staging_, error);
    fail("no permission to create files in " + parent.string());
  }
  target_ = normal;
}

StagedFolder::~StagedFolder() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

void StagedFolder::commit() {
  std::error_code error;
  if (fs::exists(target_, error)) {
    // One exchange: the target is the new folder at once, the staging path the old one.
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
      fs::remove_all(staging_, error);
    } else if (errno == EINVAL || errno == ENOSYS) {
      // A file system without exchange: two renames, the old folder under a staging name (a
      // crash between them leaves no target, and the next run clears the old one).
      const fs::path old = staging_.string() + "-old";
      fs::rename(target_, old, error);
      if (!error) {
        fs::rename(staging_, target_, error);
      }
      if (error) {
        fail(error.message());
      }
      fs::remove_all(old, error);
    } else {
      const int reason = errno;
      fail(std::generic_category().message(reason));
    }
  } else {
    fs::rename(staging_, target_, error);
    if (error) {
      fail(error.message());
    }
  }
  committed_ = true;
}

void StagedFolder::fail(const std::string& why) const {
  throw InputError(option_ + " " + target_.string() + ": cannot write (" + why + ")");
}

}  // namespace softbench::harness
