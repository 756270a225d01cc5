// SPDX-License-Identifier: MIT
// softbench: the command line. Bad input (a bad option, a bad file) exits 2 with one line naming
// the option or the file and the problem; Ctrl-C or SIGTERM stops between two steps and exits 130
// (files already written stay whole, none is left half-written); any other failure exits 1.
#include "geometry/input_error.h"
#include "harness/calibrate/calibration.h"
#include "harness/cli/commands.h"
#include "harness/interrupt.h"
#include "harness/provenance.h"

#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{
      "softbench: a soft-body physics testbed (mass-spring, corotational FEM, shape "
      "matching, Bullet) on a liver scene"};
  app.require_subcommand(1);
  app.set_version_flag("--version", softbench::harness::version_line());
  using namespace softbench::harness;
  for (auto add : {add_run_command, add_compare_command, add_sweep_command, add_merge_command,
                   add_recommend_command, add_stability_command, add_calibrate_command,
                   add_verify_command, add_soak_command, add_snapshot_command, add_view_command,
                   add_models_command, add_mesh_command}) {
    add(app);
  }
  install_interrupt_handlers();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) {
      return app.exit(error);  // --help, --version
    }
    // A bad option is bad input like any other: status 2 and one line (CLI11's own codes start
    // at 100, which scripts would take for a crash).
    std::cerr << "softbench: error: " << error.what() << " (see --help)\n";
    return 2;
  } catch (const Interrupted& interrupted) {
    std::cerr << "softbench: interrupted: " << interrupted.what() << "\n";
    return 130;
  } catch (const softbench::InputError& error) {
    std::cerr << "softbench: error: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "softbench: internal error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
