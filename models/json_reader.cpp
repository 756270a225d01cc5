// SPDX-License-Identifier: MIT
#include "models/json_reader.h"

#include "geometry/input_error.h"
#include "geometry/text_format.h"

#include <algorithm>
#include <cmath>

namespace softbench {
namespace {

std::string shown(const nlohmann::json& value) {
  std::string text = value.dump();
  constexpr std::size_t kMaxShown = 60;
  if (text.size() > kMaxShown) {
    text = text.substr(0, kMaxShown) + "...";
  }
  return text;
}

}  // namespace

bool Range::contains(double value) const {
  if (!std::isfinite(value)) {
    return false;
  }
  const bool above = min_inclusive ? value >= min : value > min;
  const bool below = max_inclusive ? value <= max : value < max;
  return above && below;
}

std::string Range::describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max) {
    return "a number in " + std::string(min_inclusive ? "[" : "(") + format_number(min) + ", "
           + format_number(max) + (max_inclusive ? "]" : ")");
  }
  if (has_min) {
    return "a number " + std::string(min_inclusive ? ">= " : "> ") + format_number(min);
  }
  if (has_max) {
    return "a number " + std::string(max_inclusive ? "<= " : "< ") + format_number(max);
  }
  return "a finite number";
}

JsonReader::JsonReader(const nlohmann::json& object, std::string source, std::string pointer)
    : object_(&object), source_(std::move(source)), pointer_(std::move(pointer)) {
  if (!object.is_object()) {
    throw InputError(source_ + ": " + (pointer_.empty() ? "/" : pointer_)
                     + ": expected an object, got " + shown(object));
  }
}

bool JsonReader::has(std::string_view key) const {
  return object_->contains(key);
}

std::string JsonReader::pointer_to(std::string_view key) const {
  return pointer_ + "/" + one_line(key);  // a key may hold a line break ("a\nb")
}

void JsonReader::fail(std::string_view key, std::string_view message) const {
  throw InputError(source_ + ": " + pointer_to(key) + ": " + std::string(message));
}

void JsonReader::fail_expected(std::string_view key, std::string_view expected) const {
  const std::string got = has(key) ? shown(object_->at(std::string(key))) : "nothing";
  fail(key, "expected " + std::string(expected) + ", got " + got);
}

const nlohmann::json& JsonReader::require(std::string_view key) const {
  read_keys_.emplace(key);
  const auto found = object_->find(key);
  if (found == object_->end()) {
    fail(key, "missing (required)");
  }
  return *found;
}

const nlohmann::json& JsonReader::raw(std::string_view key) const {
  return require(key);
}

const nlohmann::json* JsonReader::find(std::string_view key) const {
  read_keys_.emplace(key);
  const auto found = object_->find(key);
  return found == object_->end() ? nullptr : &*found;
}

double JsonReader::number(std::string_view key, Range range) const {
  const nlohmann::json& value = require(key);
  if (!value.is_number() || !range.contains(value.get<double>())) {
    fail_expected(key, range.describe());
  }
  return value.get<double>();
}

double JsonReader::number_or(std::string_view key, double fallback, Range range) const {
  read_keys_.emplace(key);
  return has(key) ? number(key, range) : fallback;
}

int JsonReader::integer(std::string_view key, int lo, int hi) const {
  const nlohmann::json& value = require(key);
  if (!value.is_number_integer() || value.get<long long>() < lo || value.get<long long>() > hi) {
    fail_expected(key, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return value.get<int>();
}

int JsonReader::integer_or(std::string_view key, int fallback, int lo, int hi) const {
  read_keys_.emplace(key);
  return has(key) ? integer(key, lo, hi) : fallback;
}

bool JsonReader::boolean_or(std::string_view key, bool fallback) const {
  read_keys_.emplace(key);
  if (!has(key)) {
    return fallback;
  }
  const nlohmann::json& value = require(key);
  if (!value.is_boolean()) {
    fail_expected(key, "true or false");
  }
  return value.get<bool>();
}

std::string JsonReader::string(std::string_view key) const {
  const nlohmann::json& value = require(key);
  if (!value.is_string()) {
    fail_expected(key, "a string");
  }
  return value.get<std::string>();
}

std::string JsonReader::choice(std::string_view key,
                               std::initializer_list<std::string_view> allowed,
                               std::string_view fallback) const {
  read_keys_.emplace(key);
  if (!has(key) && !fallback.empty()) {
    return std::string(fallback);
  }
  const nlohmann::json& value = require(key);
  std::string options;
  for (std::string_view option : allowed) {
    if (value.is_string() && value.get<std::string>() == option) {
      return std::string(option);
    }
    options += (options.empty() ? "\"" : ", \"") + std::string(option) + "\"";
  }
  fail_expected(key, "one of " + options);
}

Eigen::Vector3d JsonReader::vector3(std::string_view key) const {
  const nlohmann::json& value = require(key);
  const bool ok = value.is_array() && value.size() == 3
                  && std::all_of(value.begin(), value.end(), [](const nlohmann::json& x) {
                       return x.is_number() && std::isfinite(x.get<double>());
                     });
  if (!ok) {
    fail_expected(key, "[x, y, z] (three finite numbers)");
  }
  return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

Eigen::Vector3d JsonReader::vector3_or(std::string_view key,
                                       const Eigen::Vector3d& fallback) const {
  read_keys_.emplace(key);
  return has(key) ? vector3(key) : fallback;
}

std::vector<int> JsonReader::integers(std::string_view key, int lo, int hi) const {
  const nlohmann::json& value = require(key);
  std::vector<int> result;
  const std::string expected =
      "an array of integers in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!value.is_array()) {
    fail_expected(key, expected);
  }
  for (std::size_t i = 0; i < value.size(); ++i) {
    const nlohmann::json& item = value[i];
    if (!item.is_number_integer() || item.get<long long>() < lo || item.get<long long>() > hi) {
      fail(std::string(key) + "/" + std::to_string(i),
           "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got "
               + shown(item));
    }
    result.push_back(item.get<int>());
  }
  return result;
}

JsonReader JsonReader::object(std::string_view key) const {
  const nlohmann::json& value = require(key);
  if (!value.is_object()) {
    fail_expected(key, "an object");
  }
  return JsonReader(value, source_, pointer_to(key));
}

std::vector<JsonReader> JsonReader::objects(std::string_view key) const {
  const nlohmann::json& value = require(key);
  if (!value.is_array()) {
    fail_expected(key, "an array of objects");
  }
  std::vector<JsonReader> result;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const std::string pointer = pointer_to(key) + "/" + std::to_string(i);
    if (!value[i].is_object()) {
      throw InputError(source_ + ": " + pointer + ": expected an object, got " + shown(value[i]));
    }
    result.emplace_back(value[i], source_, pointer);
  }
  return result;
}

void JsonReader::reject_unknown_keys() const {
  for (const auto& [key, value] : object_->items()) {
    if (!read_keys_.contains(key)) {
      std::string known;
      for (const std::string& read : read_keys_) {
        known += (known.empty() ? "" : ", ") + read;
      }
      fail(key, "unknown key (known here: " + known + ")");
    }
  }
}

}  // namespace softbench
