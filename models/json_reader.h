// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <initializer_list>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace softbench {

/// An interval a number must lie in, with its own description for messages.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  bool max_inclusive = true;

  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), false, true}; }
  static Range non_negative() { return {0.0, std::numeric_limits<double>::infinity()}; }
  static Range closed(double lo, double hi) { return {lo, hi}; }
  static Range half_open(double lo, double hi) { return {lo, hi, true, false}; }

  bool contains(double value) const;
  std::string describe() const;  ///< "a number in [0, 0.5)", "a number > 0"
};

/// Reads one JSON object with messages that name the file, the JSON pointer and what was
/// expected, e.g. `scenes/liver.json: /material/poisson_ratio: expected a number in [0, 0.5),
/// got 0.5` (polyfem's validated input, made specific). Every key read is remembered so
/// reject_unknown_keys() can name a misspelt one. Errors throw InputError.
class JsonReader {
 public:
  /// `object` must outlive the reader. `pointer` is where it sits in the file ("" = root).
  JsonReader(const nlohmann::json& object, std::string source, std::string pointer = "");

  bool has(std::string_view key) const;
  std::string pointer_to(std::string_view key) const;  ///< "/material/density"
  const std::string& source() const { return source_; }

  double number(std::string_view key, Range range = {}) const;  ///< required
  double number_or(std::string_view key, double fallback, Range range = {}) const;
  int integer(std::string_view key, int lo, int hi) const;  ///< required, in [lo, hi]
  int integer_or(std::string_view key, int fallback, int lo, int hi) const;
  bool boolean_or(std::string_view key, bool fallback) const;
  std::string string(std::string_view key) const;  ///< required
  /// One of `allowed`; required when `fallback` is empty.
  std::string choice(std::string_view key,
                     std::initializer_list<std::string_view> allowed,
                     std::string_view fallback = {}) const;
  Eigen::Vector3d vector3(std::string_view key) const;  ///< required [x, y, z], finite
  Eigen::Vector3d vector3_or(std::string_view key, const Eigen::Vector3d& fallback) const;
  std::vector<int> integers(std::string_view key, int lo, int hi) const;  ///< required array

  JsonReader object(std::string_view key) const;  ///< required nested object
  /// Each element of a required array of objects, in order.
  std::vector<JsonReader> objects(std::string_view key) const;
  const nlohmann::json& raw(std::string_view key) const;   ///< required, any type
  const nlohmann::json* find(std::string_view key) const;  ///< optional, any type; null if absent

  /// Throws naming the first key present in the object but never read.
  void reject_unknown_keys() const;
  /// Throws "<source>: <pointer to key>: <message>".
  [[noreturn]] void fail(std::string_view key, std::string_view message) const;
  /// Throws "<source>: <pointer to key>: expected <expected>, got <the value>".
  [[noreturn]] void fail_expected(std::string_view key, std::string_view expected) const;

 private:
  const nlohmann::json& require(std::string_view key) const;

  const nlohmann::json* object_;
  std::string source_;
  std::string pointer_;
  mutable std::set<std::string, std::less<>> read_keys_;
};


}  // namespace softbench
