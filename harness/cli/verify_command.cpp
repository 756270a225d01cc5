// SPDX-License-Identifier: MIT
// `softbench verify`: the analytic verification cases, a table of errors per model.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "harness/report/staged_folder.h"
#include "harness/report/verify_report.h"
#include "harness/verify/verify.h"

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

struct VerifyArguments {
  std::vector<std::string> models;
  std::vector<std::string> cases;
  std::string out_dir;
  bool quick = false;
};

void verify(const VerifyArguments& arguments) {
  StagedFolder out(out_dir_or(arguments.out_dir, std::filesystem::path("out") / "verify"), "--out");
  VerifyOptions options;
  options.models = arguments.models;
  options.cases = arguments.cases;
  options.settings = arguments.quick ? quick_verify_settings() : default_verify_settings();
  options.progress = &std::cerr;
  const VerifyReport report = run_verify(options);
  write_verify(out.path(), report);
  out.commit();
  std::cout << verify_markdown(report) << "\nwrote " << (out.path() / "verify.md").string()
            << " and " << (out.path() / "verify.json").string() << "\n";
  std::cerr << "verify took " << std::fixed << std::setprecision(1) << report.wall_seconds
            << " s\n";
}

}  // namespace

void add_verify_command(CLI::App& app) {
  auto arguments = std::make_shared<VerifyArguments>();
  CLI::App* command = app.add_subcommand(
      "verify",
      "Run the analytic verification cases (patch test, rigid-motion invariance, cantilever vs "
      "Euler-Bernoulli under refinement, sphere indentation vs Hertz, free spin, squash and "
      "release) on each model; write verify.md and verify.json with each case's error, "
      "tolerance and PASS/FAIL. Exits 0 when every case ran, whatever the verdicts");
  add_model_option(*command, arguments->models, "every registered model but the references");
  command
      ->add_option("--case", arguments->cases,
                   "case to run (repeatable; default: all of patch, rigid_motion, cantilever, "
                   "hertz, free_spin, squash_release)")
      ->allow_extra_args(false);
  add_out_option(*command, arguments->out_dir, "out/verify");
  command->add_flag("--quick", arguments->quick,
                    "coarse variants for CI: two cantilever levels, a coarser Hertz block, "
                    "shorter runs");
  command->callback([arguments] { verify(*arguments); });
}

}  // namespace softbench::harness
