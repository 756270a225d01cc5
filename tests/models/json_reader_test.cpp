// SPDX-License-Identifier: MIT
#include "models/json_reader.h"

#include "geometry/input_error.h"
#include "models/param_table.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softbench {
namespace {

using ::testing::HasSubstr;

template <class Read>
std::string error_of(Read read) {
  try {
    read();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

const nlohmann::json kScene = nlohmann::json::parse(R"({
  "material": {"poisson_ratio": 0.5, "density": "heavy"},
  "time": {"dt": 0.01, "dtt": 1},
  "gravity": [0, 0],
  "fixed": {"vertices": [1, 2, -3]},
  "type": "cubic"
})");

TEST(JsonReader, NamesTheFilePointerExpectationAndValue) {
  const JsonReader scene(kScene, "scenes/x.json");
  EXPECT_EQ(
      error_of([&] { scene.object("material").number("poisson_ratio", Range::half_open(0, 0.5)); }),
      "scenes/x.json: /material/poisson_ratio: expected a number in [0, 0.5), got 0.5");
  EXPECT_EQ(error_of([&] { scene.object("material").number("density", Range::positive()); }),
            "scenes/x.json: /material/density: expected a number > 0, got \"heavy\"");
  EXPECT_THAT(error_of([&] { scene.vector3("gravity"); }),
              HasSubstr("/gravity: expected [x, y, z] (three finite numbers), got [0,0]"));
  EXPECT_THAT(error_of([&] { scene.object("fixed").integers("vertices", 0, 10); }),
              HasSubstr("/fixed/vertices/2: expected an integer in [0, 10], got -3"));
  EXPECT_THAT(error_of([&] {
                scene.choice("type", {"linear", "quadratic"});
              }),
              HasSubstr("/type: expected one of \"linear\", \"quadratic\", got \"cubic\""));
  EXPECT_THAT(error_of([&] { scene.number("duration"); }), HasSubstr("/duration: missing"));
}

TEST(JsonReader, RejectsAKeyNobodyRead) {
  const JsonReader time(kScene["time"], "x.json", "/time");
  EXPECT_EQ(time.number("dt", Range::positive()), 0.01);
  EXPECT_THAT(error_of([&] { time.reject_unknown_keys(); }),
              HasSubstr("x.json: /time/dtt: unknown key (known here: dt)"));
}

TEST(JsonReader, FillsDefaultsForAbsentOptionalKeys) {
  const JsonReader time(kScene["time"], "x.json", "/time");
  EXPECT_EQ(time.number_or("duration", 2.5, Range::positive()), 2.5);
  EXPECT_EQ(time.integer_or("substeps", 3, 1, 10), 3);
  EXPECT_TRUE(time.boolean_or("adaptive", true));
}

struct ExampleParams {
  enum class Mode { kFast, kExact };
  double stiffness = 2.0;
  int iterations = 10;
  bool warm_start = true;
  Mode mode = Mode::kFast;
};

ParamTable<ExampleParams> example_table() {
  ParamTable<ExampleParams> table;
  table.number("stiffness", &ExampleParams::stiffness, Range::positive(), "N/m")
      .integer("iterations", &ExampleParams::iterations, 1, 100, "count")
      .boolean("warm_start", &ExampleParams::warm_start, "reuse the last solution")
      .choice("mode", &ExampleParams::mode,
              {{"fast", ExampleParams::Mode::kFast}, {"exact", ExampleParams::Mode::kExact}},
              "speed or accuracy");
  return table;
}

TEST(ParamTable, ReadsEchoesAndDocumentsEachParameterOnce) {
  const auto table = example_table();
  const ExampleParams params =
      table.read(nlohmann::json{{"mode", "exact"}, {"iterations", 7}}, "s.json", "/models/x");
  EXPECT_EQ(params.mode, ExampleParams::Mode::kExact);
  EXPECT_EQ(params.iterations, 7);
  EXPECT_EQ(params.stiffness, 2.0);
  const nlohmann::json echoed = table.to_json(params);
  EXPECT_EQ(echoed,
            (nlohmann::json{
                {"stiffness", 2.0}, {"iterations", 7}, {"warm_start", true}, {"mode", "exact"}}));
  const ExampleParams again = table.read(echoed, "s.json", "/models/x");
  EXPECT_EQ(table.to_json(again), echoed);
  ASSERT_EQ(table.docs().size(), 4u);
  EXPECT_EQ(table.docs()[3].default_value, "fast");
}

TEST(ParamTable, RejectsUnknownKeysWrongTypesAndValuesOutOfRange) {
  const auto table = example_table();
  EXPECT_THAT(error_of([&] {
                table.read(nlohmann::json{{"stifness", 1.0}}, "s.json", "/models/x");
              }),
              HasSubstr("s.json: /models/x/stifness: unknown key"));
  EXPECT_THAT(error_of([&] {
                table.read(nlohmann::json{{"stiffness", -1.0}}, "s.json", "/models/x");
              }),
              HasSubstr("/models/x/stiffness: expected a number > 0, got -1.0"));
  EXPECT_THAT(error_of([&] {
                table.read(nlohmann::json{{"mode", 2}}, "s.json", "/models/x");
              }),
              HasSubstr("/models/x/mode: expected one of \"fast\", \"exact\", got 2"));
  EXPECT_THAT(error_of([&] {
                table.read(nlohmann::json{{"warm_start", "yes"}}, "s.json", "/m");
              }),
              HasSubstr("/m/warm_start: expected true or false"));
}

}  // namespace
}  // namespace softbench
