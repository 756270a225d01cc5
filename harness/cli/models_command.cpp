// SPDX-License-Identifier: MIT
// `softbench models [--json]`: the registry as a user reads it.
#include "harness/cli/commands.h"
#include "models/model_registry.h"

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>
#include <string>

namespace softbench::harness {
namespace {

void list_models(bool json) {
  const ModelRegistry& registry = builtin_models();
  if (json) {
    nlohmann::json list = nlohmann::json::array();
    for (const std::string& name : registry.names()) {
      const ModelInfo& info = registry.at(name);
      nlohmann::json parameters = nlohmann::json::array();
      for (const ParameterDoc& doc : info.parameters) {
        parameters.push_back(
            {{"name", doc.name}, {"default", doc.default_value}, {"description", doc.description}});
      }
      list.push_back({{"name", name}, {"summary", info.summary}, {"parameters", parameters}});
    }
    std::cout << list.dump(2) << "\n";
    return;
  }
  for (const std::string& name : registry.names()) {
    const ModelInfo& info = registry.at(name);
    std::cout << name << ": " << info.summary << "\n";
    for (const ParameterDoc& doc : info.parameters) {
      std::cout << "  " << doc.name << " = " << doc.default_value.dump() << "  (" << doc.description
                << ")\n";
    }
  }
}

}  // namespace

void add_models_command(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  CLI::App* models = app.add_subcommand("models", "List the models with their parameters");
  models->add_flag("--json", *json, "as JSON");
  models->callback([json] { list_models(*json); });
}

}  // namespace softbench::harness
