// SPDX-License-Identifier: MIT
#include "harness/report/python_plot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <system_error>

extern char** environ;  // NOLINT: POSIX, for posix_spawnp

namespace softbench::harness {
namespace {

namespace fs = std::filesystem;

struct ProcessResult {
  bool started = false;
  int exit_status = -1;  ///< -1 when killed by a signal or not started
  std::string out;       ///< its stdout
};

// Runs argv[0] (searched on the PATH) without a shell, so no path needs quoting. stderr is
// inherited, or discarded when `quiet`; stdout is captured.
ProcessResult run_process(const std::vector<std::string>& argv, bool quiet) {
  ProcessResult result;
  std::array<int, 2> pipe_ends{};
  if (::pipe(pipe_ends.data()) != 0) {
    return result;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_ends[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_ends[0]);
  posix_spawn_file_actions_addclose(&actions, pipe_ends[1]);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  }
  std::vector<char*> args;
  for (const std::string& arg : argv) {
    args.push_back(const_cast<char*>(arg.c_str()));  // posix_spawn's signature; not modified
  }
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_ends[1]);
  if (spawned != 0) {
    ::close(pipe_ends[0]);
    return result;
  }
  result.started = true;
  std::array<char, 4096> buffer{};
  ssize_t count = 0;
  while ((count = ::read(pipe_ends[0], buffer.data(), buffer.size())) > 0) {
    result.out.append(buffer.data(), static_cast<std::size_t>(count));
  }
  ::close(pipe_ends[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      return result;
    }
  }
  if (WIFEXITED(status)) {
    result.exit_status = WEXITSTATUS(status);
  }
  return result;
}

bool is_file(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

std::optional<fs::path> executable_dir() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) {
    return std::nullopt;
  }
  return self.parent_path();
}

}  // namespace

std::optional<fs::path> find_plot_script(const std::string& name, const char* env_var) {
  if (const char* configured = std::getenv(env_var); configured != nullptr) {
    return is_file(configured) ? std::optional<fs::path>(configured) : std::nullopt;
  }
  std::vector<fs::path> candidates;
#ifdef SOFTBENCH_TOOLS_DIR
  candidates.push_back(fs::path(SOFTBENCH_TOOLS_DIR) / name);
#endif
  if (const std::optional<fs::path> dir = executable_dir()) {
    candidates.push_back(*dir / name);
    candidates.push_back(*dir / ".." / "tools" / name);
  }
  for (const fs::path& candidate : candidates) {
    if (is_file(candidate)) {
      return candidate.lexically_normal();
    }
  }
  return std::nullopt;
}

std::optional<std::string> plotting_python() {
  std::vector<std::string> candidates;
  if (const char* configured = std::getenv("SOFTBENCH_PYTHON"); configured != nullptr) {
    candidates.emplace_back(configured);
  } else {
    candidates = {"python3", "/usr/bin/python3"};
  }
  for (const std::string& python : candidates) {
    const ProcessResult probe = run_process({python, "-c", "import matplotlib"}, true);
    if (probe.started && probe.exit_status == 0) {
      return python;
    }
  }
  return std::nullopt;
}

PlotOutcome run_plot_script(const std::string& script_name,
                            const char* env_var,
                            const fs::path& json_file,
                            const fs::path& out_dir) {
  PlotOutcome outcome;
  const std::optional<fs::path> script = find_plot_script(script_name, env_var);
  if (!script) {
    outcome.message = "plots skipped: tools/" + script_name
                      + " not found (looked in the source tree and beside the executable; set "
                      + env_var + " to its path)";
    return outcome;
  }
  const std::optional<std::string> python = plotting_python();
  if (!python) {
    const char* configured = std::getenv("SOFTBENCH_PYTHON");
    outcome.message = "plots skipped: no Python with matplotlib (tried "
                      + (configured != nullptr ? "SOFTBENCH_PYTHON=" + std::string(configured)
                                               : std::string("python3 and /usr/bin/python3"))
                      + "); install python3-matplotlib (scripts/setup does), then run `python3 "
                      + script->string() + " " + json_file.string() + "`";
    return outcome;
  }
  const ProcessResult run = run_process(
      {*python, script->string(), json_file.string(), "--out", out_dir.string()}, false);
  if (!run.started || run.exit_status != 0) {
    outcome.message = "plots failed: " + *python + " " + script->string() + " exited with "
                      + (run.started ? "status " + std::to_string(run.exit_status)
                                     : std::string("an error starting it"));
    return outcome;
  }
  std::istringstream lines(run.out);
  std::string line;
  while (std::getline(lines, line)) {
    if (!line.empty() && is_file(line)) {
      outcome.files.emplace_back(line);
    }
  }
  std::sort(outcome.files.begin(), outcome.files.end());
  outcome.plotted = true;
  return outcome;
}

void print_plot_outcome(const PlotOutcome& outcome) {
  if (!outcome.plotted) {
    std::cerr << "softbench: warning: " << outcome.message << "\n";
  }
  for (const std::filesystem::path& file : outcome.files) {
    std::cout << "wrote " << file.string() << "\n";
  }
}

PlotOutcome landed(PlotOutcome outcome, const StagedFolder& folder) {
  for (std::filesystem::path& file : outcome.files) {
    file = folder.landed(file);
  }
  return outcome;
}

}  // namespace softbench::harness
