// SPDX-License-Identifier: MIT
#include "viewer/input_script.h"

#include "geometry/input_error.h"
#include "models/json_file.h"
#include "models/json_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace softbench::viewer {
namespace {

constexpr double kMaxTime = 24.0 * 3600.0;  ///< s: a day of scripted input
constexpr double kMaxPixel = 65536.0;

Eigen::Vector2d pixel(const JsonReader& event, const std::string& key) {
  const nlohmann::json& value = event.raw(key);
  if (!value.is_array() || value.size() != 2 || !value[0].is_number() || !value[1].is_number()
      || std::abs(value[0].get<double>()) > kMaxPixel
      || std::abs(value[1].get<double>()) > kMaxPixel) {
    event.fail_expected(key, "[x, y] in pixels of the window");
  }
  return {value[0].get<double>(), value[1].get<double>()};
}

}  // namespace

std::vector<InputEvent> read_input_script(const std::filesystem::path& path) {
  const nlohmann::json document = read_json_file(path, "viewer input script");
  const JsonReader root(document, path.string());
  const std::vector<JsonReader> entries = root.objects("events");
  root.reject_unknown_keys();
  if (entries.size() > static_cast<std::size_t>(kMaxInputEvents)) {
    throw InputError(path.string() + ": /events: " + std::to_string(entries.size())
                     + " events, more than the limit of " + std::to_string(kMaxInputEvents));
  }
  std::vector<InputEvent> events;
  for (const JsonReader& entry : entries) {
    InputEvent event;
    event.time = entry.number("t", Range::closed(0.0, kMaxTime));
    int actions = 0;
    if (entry.has("mouse_down")) {
      event.kind = InputEvent::Kind::kMouseDown;
      event.pixel = pixel(entry, "mouse_down");
      ++actions;
    }
    if (entry.has("mouse_move")) {
      event.kind = InputEvent::Kind::kMouseMove;
      event.pixel = pixel(entry, "mouse_move");
      ++actions;
    }
    if (entry.find("mouse_up") != nullptr) {
      event.kind = InputEvent::Kind::kMouseUp;
      ++actions;
    }
    if (entry.has("key")) {
      const std::string key = entry.string("key");
      if (key == "space") {
        event.key = ' ';
      } else if (key.size() == 1 && std::isalpha(static_cast<unsigned char>(key[0])) != 0) {
        event.key = static_cast<char>(std::tolower(static_cast<unsigned char>(key[0])));
      } else {
        entry.fail_expected("key", "one letter, or \"space\"");
      }
      event.kind = InputEvent::Kind::kKey;
      ++actions;
    }
    if (entry.has("screenshot")) {
      event.kind = InputEvent::Kind::kScreenshot;
      event.file = entry.string("screenshot");
      ++actions;
    }
    if (entry.find("quit") != nullptr) {
      event.kind = InputEvent::Kind::kQuit;
      ++actions;
    }
    entry.reject_unknown_keys();
    if (actions != 1) {
      entry.fail("t", "an event needs exactly one of mouse_down, mouse_move, mouse_up, key, "
                      "screenshot, quit");
    }
    events.push_back(event);
  }
  std::stable_sort(events.begin(), events.end(),
                   [](const InputEvent& a, const InputEvent& b) { return a.time < b.time; });
  return events;
}

}  // namespace softbench::viewer
