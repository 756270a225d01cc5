// SPDX-License-Identifier: MIT
// The one list of models: adding a model = its folder + one line here.
#include "models/mass_spring/mass_spring.h"
#include "models/model_registry.h"

namespace softbench {
namespace {

ModelRegistry make_builtin_registry() {
  ModelRegistry registry;
  registry.add(mass_spring_info());
  return registry;
}

}  // namespace

const ModelRegistry& builtin_models() {
  static const ModelRegistry registry = make_builtin_registry();
  return registry;
}

}  // namespace softbench
