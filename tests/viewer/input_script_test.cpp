// SPDX-License-Identifier: MIT
// The viewer's scripted input: read in time order, every mistake one line naming the file and
// the event's key.
#include "viewer/input_script.h"

#include "geometry/input_error.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softbench::viewer {
namespace {

using ::testing::HasSubstr;

TEST(InputScript, ReadsEveryKindOfEventInTimeOrder) {
  const test::TempDir dir;
  const auto file = dir.write("input.json", R"({"events": [
    {"t": 3.0, "mouse_up": true},
    {"t": 1.0, "mouse_down": [400, 300]},
    {"t": 2.0, "mouse_move": [400, 350.5]},
    {"t": 2.5, "key": "G"},
    {"t": 2.6, "key": "space"},
    {"t": 3.5, "screenshot": "out.png"},
    {"t": 4.0, "quit": true}]})");
  const std::vector<InputEvent> events = read_input_script(file);
  ASSERT_EQ(events.size(), 7U);
  EXPECT_EQ(events[0].kind, InputEvent::Kind::kMouseDown);
  EXPECT_EQ(events[0].pixel, Eigen::Vector2d(400.0, 300.0));
  EXPECT_EQ(events[1].kind, InputEvent::Kind::kMouseMove);
  EXPECT_EQ(events[1].pixel.y(), 350.5);
  EXPECT_EQ(events[2].key, 'g');
  EXPECT_EQ(events[3].key, ' ');
  EXPECT_EQ(events[4].kind, InputEvent::Kind::kMouseUp);
  EXPECT_EQ(events[5].file, "out.png");
  EXPECT_EQ(events[6].kind, InputEvent::Kind::kQuit);
}

void expect_rejected(const std::string& events, const std::string& message) {
  const test::TempDir dir;
  const auto file = dir.write("input.json", R"({"events": [)" + events + "]}");
  try {
    read_input_script(file);
    FAIL() << "accepted " << events;
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(file.string()));
    EXPECT_THAT(error.what(), HasSubstr(message)) << error.what();
  }
}

TEST(InputScript, NamesTheFileAndTheKeyOfABadEvent) {
  expect_rejected(R"({"t": -1, "quit": true})", "/events/0/t");
  expect_rejected(R"({"t": 1, "mouse_down": [1]})", "/events/0/mouse_down");
  expect_rejected(R"({"t": 1, "mouse_down": [1, 1e300]})", "/events/0/mouse_down");
  expect_rejected(R"({"t": 1, "key": "F1"})", "/events/0/key");
  expect_rejected(R"({"t": 1})", "exactly one of");
  expect_rejected(R"({"t": 1, "quit": true, "mouse_up": true})", "exactly one of");
  expect_rejected(R"({"t": 1, "quit": true, "qiut": true})", "qiut");
}

}  // namespace
}  // namespace softbench::viewer
