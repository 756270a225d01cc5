// SPDX-License-Identifier: MIT
#include "models/model_registry.h"

#include "geometry/input_error.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softbench {
namespace {

TEST(ModelRegistry, ListsTheBuiltinModelsSorted) {
  const std::vector<std::string> names = builtin_models().names();
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  EXPECT_THAT(names, ::testing::Contains("mass_spring"));
  for (const std::string& name : names) {
    const ModelInfo& info = builtin_models().at(name);
    EXPECT_EQ(info.name, name);
    EXPECT_FALSE(info.summary.empty()) << name;
    EXPECT_FALSE(info.parameters.empty()) << name;
    for (const ParameterDoc& doc : info.parameters) {
      EXPECT_FALSE(doc.description.empty()) << name << "." << doc.name;
    }
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
