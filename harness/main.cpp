// SPDX-License-Identifier: MIT
// softbench: the command line. Bad input exits 2 with one line naming the file and the problem;
// any other failure exits 1.
#include "geometry/input_error.h"
#include "harness/calibrate_command.h"
#include "harness/compare_command.h"
#include "harness/mesh_commands.h"
#include "harness/run_commands.h"
#include "harness/stability_command.h"
#include "harness/sweep_command.h"

#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{
      "softbench: a soft-body physics testbed (mass-spring, corotational FEM, shape "
      "matching, Bullet) on a liver scene"};
  app.require_subcommand(1);
  softbench::harness::add_mesh_commands(app);
  softbench::harness::add_run_commands(app);
  softbench::harness::add_calibrate_command(app);
  softbench::harness::add_compare_command(app);
  softbench::harness::add_stability_command(app);
  softbench::harness::add_sweep_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  } catch (const softbench::InputError& error) {
    std::cerr << "softbench: error: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "softbench: internal error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
