// SPDX-License-Identifier: MIT
// Fuzzes the models' parameter blocks. The input is a scene's "models" object ({"mass_spring":
// {...}, ...}) as JSON text, read through the bounded reader; each block is checked as `softbench
// run` checks a scene's blocks before any model runs (harness/run/runner.cpp): the name against
// the registry, then the model built from the block on one cube of six tets, which validates
// every parameter through its ParamTable. A model that builds must echo its parameters
// (SoftBody::parameters) as a block that builds again.
#include "fuzz/fuzz_support.h"
#include "geometry/input_error.h"
#include "geometry/mesh_validation.h"
#include "geometry/shape_meshes.h"
#include "models/json_file.h"
#include "models/json_reader.h"
#include "models/material.h"
#include "models/model_registry.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fuzz = softbench::fuzz;
  using softbench::builtin_models;
  static const std::string source = "fuzz_models.json";
  static const softbench::TetMesh one_cube =
      softbench::make_tet_mesh(softbench::box_tets(1, 1, 1, 0.01, 0.01, 0.01));
  static const softbench::Material material;
  const std::string text = fuzz::as_text(data, size);
  fuzz::expect_only_input_errors(source, [&] {
    const nlohmann::json blocks = softbench::parse_json_text(text, source);
    const softbench::JsonReader models(blocks, source, "/models");  // an object, or InputError
    for (const auto& [name, block] : blocks.items()) {
      if (builtin_models().unavailable(name)) {
        continue;  // a block for a model this build leaves out is no error
      }
      if (!builtin_models().contains(name)) {
        try {
          builtin_models().at(name);
        } catch (const softbench::InputError& error) {
          models.fail(name, error.what());
        }
        fuzz::finding("registry.at(\"" + name + "\") found a model contains() does not");
      }
      const softbench::ModelInfo& info = builtin_models().at(name);
      const softbench::ParamSource where{source, "/models/" + name};
      const std::unique_ptr<softbench::SoftBody> body =
          info.create(one_cube, material, block, where);
      const nlohmann::json echo = body->parameters();
      try {
        static_cast<void>(info.create(one_cube, material, echo, where));
      } catch (const softbench::InputError& error) {
        fuzz::finding("model " + name + " does not build from its own parameters "
                      + echo.dump() + ": " + error.what());
      }
    }
  });
  return 0;
}
