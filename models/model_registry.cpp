// SPDX-License-Identifier: MIT
#include "models/model_registry.h"

#include "geometry/input_error.h"
#include "geometry/text_format.h"

#include <stdexcept>

namespace softbench {

void ModelRegistry::add(ModelInfo info) {
  const std::string name = info.name;
  if (!models_.emplace(name, std::move(info)).second) {
    throw std::logic_error("model registered twice: " + name);
  }
}

void ModelRegistry::add_unavailable(std::string name, std::string reason) {
  unavailable_.emplace(std::move(name), std::move(reason));
}

bool ModelRegistry::unavailable(std::string_view name) const {
  return unavailable_.contains(name);
}

const ModelInfo& ModelRegistry::at(std::string_view name) const {
  const auto found = models_.find(name);
  if (const auto left_out = unavailable_.find(name); left_out != unavailable_.end()) {
    throw InputError("model \"" + one_line(name) + "\" is not in this build (" + left_out->second
                     + ")");
  }
  if (found == models_.end()) {
    std::string known;
    for (const auto& [key, info] : models_) {
      known += (known.empty() ? "" : ", ") + key;
    }
    throw InputError("unknown model \"" + one_line(name) + "\" (known: " + known + ")");
  }
  return found->second;
}

bool ModelRegistry::contains(std::string_view name) const {
  return models_.contains(name);
}

std::vector<std::string> ModelRegistry::names() const {
  std::vector<std::string> result;
  for (const auto& [name, info] : models_) {
    result.push_back(name);
  }
  return result;
}

std::vector<std::string> ModelRegistry::default_names() const {
  std::vector<std::string> result;
  for (const auto& [name, info] : models_) {
    if (!info.reference) {
      result.push_back(name);
    }
  }
  return result;
}

}  // namespace softbench
