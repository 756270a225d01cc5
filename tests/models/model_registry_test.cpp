// SPDX-License-Identifier: MIT
#include "models/model_registry.h"

#include "geometry/input_error.h"
#include "geometry/mesh_validation.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace softbench {
namespace {

bool documents(const ModelInfo& info, const std::string& key) {
  return std::any_of(info.parameters.begin(), info.parameters.end(),
                     [&](const ParameterDoc& doc) { return doc.name == key; });
}

TEST(ModelRegistry, EveryEntryDeclaresWhatTheHarnessNeeds) {
  const std::vector<std::string> names = builtin_models().names();
  EXPECT_THAT(names, ::testing::Contains("mass_spring"));
  for (const std::string& name : names) {
    const ModelInfo& info = builtin_models().at(name);
    EXPECT_EQ(info.name, name);
    EXPECT_FALSE(info.summary.empty()) << name;
    EXPECT_FALSE(info.parameters.empty()) << name;
    for (const ParameterDoc& doc : info.parameters) {
      EXPECT_FALSE(doc.description.empty()) << name << "." << doc.name;
    }
    // The stability map varies Young's modulus, or a parameter the model documents.
    const StiffnessAxisSpec& axis = info.stiffness_axis;
    if (axis.material) {
      EXPECT_EQ(axis.parameter, "young_modulus") << name;
    } else {
      EXPECT_TRUE(documents(info, axis.parameter)) << name << ": axis " << axis.parameter;
    }
    EXPECT_FALSE(axis.note.empty()) << name;
    for (const auto& [key, value] : axis.fixed_params.items()) {
      EXPECT_TRUE(documents(info, key)) << name << ": fixed " << key;
    }
    // Settling damping names damping parameters the model has, with values it accepts.
    for (const auto& [key, value] : info.settling_damping.items()) {
      EXPECT_TRUE(documents(info, key)) << name << ": settling " << key;
    }
    EXPECT_NO_THROW(info.create(make_tet_mesh(test::box_tets(1, 1, 1, 0.1, 0.1, 0.1)), Material{},
                                info.settling_damping, ParamSource{}))
        << name;
  }
}

TEST(ModelRegistry, DefaultRunsLeaveOutTheSlowReference) {
  const std::vector<std::string> defaults = builtin_models().default_names();
  EXPECT_THAT(defaults, ::testing::Contains("corotational_fem"));
  EXPECT_THAT(defaults, ::testing::Not(::testing::Contains("neo_hookean")));
  EXPECT_TRUE(builtin_models().at("neo_hookean").reference);
  EXPECT_EQ(defaults.size() + 1, builtin_models().names().size());
}

TEST(ModelRegistry, AnUnknownNameListsTheKnownOnes) {
  try {
    builtin_models().at("fem9000");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("unknown model \"fem9000\" (known: "));
    EXPECT_THAT(error.what(), ::testing::HasSubstr("mass_spring"));
  }
}

// Found by fuzz_model_params: a scene's model name with a line break ("fem\n9000") was quoted
// as it was, breaking the message's line.
TEST(ModelRegistry, QuotesAnUnknownNameOnOneLine) {
  try {
    builtin_models().at("fem\n9000");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), ::testing::StartsWith("unknown model \"fem\\n9000\" (known: "));
  }
}

TEST(ModelRegistry, RefusesToRegisterANameTwice) {
  ModelRegistry registry;
  ModelInfo first;
  first.name = "a";
  first.summary = "first";
  registry.add(first);
  ModelInfo second = first;
  second.summary = "second";
  EXPECT_THROW(registry.add(second), std::logic_error);
}

}  // namespace
}  // namespace softbench

namespace softbench {
namespace {

TEST(ModelRegistry, NamesTheReasonAModelIsNotInThisBuild) {
  ModelRegistry registry;
  registry.add_unavailable("bullet_softbody", "configured with SOFTBENCH_WITH_BULLET=OFF");
  EXPECT_TRUE(registry.unavailable("bullet_softbody"));
  EXPECT_FALSE(registry.contains("bullet_softbody"));
  try {
    registry.at("bullet_softbody");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("not in this build (configured with"));
  }
}

}  // namespace
}  // namespace softbench
