// SPDX-License-Identifier: MIT
#include "models/calibration_record.h"

#include <limits>

namespace softbench {
namespace {

std::vector<double> numbers(const JsonReader& in, const std::string& key, Range range) {
  std::vector<double> values;
  const nlohmann::json* array = in.find(key);
  if (array == nullptr) {
    return values;
  }
  if (!array->is_array() || array->size() > 16) {
    in.fail_expected(key, "an array of at most 16 numbers");
  }
  for (const nlohmann::json& value : *array) {
    if (!value.is_number() || !range.contains(value.get<double>())) {
      in.fail_expected(key, "an array of numbers, each " + range.describe());
    }
    values.push_back(value.get<double>());
  }
  return values;
}

}  // namespace

std::optional<CalibrationRecord> read_calibration_record(const JsonReader& in,
                                                         const std::string& key) {
  const nlohmann::json* value = in.find(key);
  if (value == nullptr || value->is_null()) {
    return std::nullopt;
  }
  if (!value->is_object()) {
    in.fail_expected(key, "null or an object {\"against\": model, \"dt\": s, \"sag\": m, ...}");
  }
  const JsonReader record = in.object(key);
  CalibrationRecord result;
  result.against = record.string("against");
  result.dt = record.number("dt", Range::positive());
  result.sag = record.number("sag");
  result.depths = numbers(record, "depths", Range::positive());
  result.forces = numbers(record, "forces", Range::non_negative());
  result.errors = numbers(record, "errors", Range{});
  if (result.forces.size() != result.depths.size()) {
    record.fail_expected("forces", "as many forces as depths");
  }
  record.reject_unknown_keys();
  return result;
}

nlohmann::json to_json(const std::optional<CalibrationRecord>& record) {
  if (!record) {
    return nullptr;
  }
  nlohmann::json json = {{"against", record->against}, {"dt", record->dt}, {"sag", record->sag}};
  if (!record->depths.empty()) {
    json["depths"] = record->depths;
    json["forces"] = record->forces;
  }
  if (!record->errors.empty()) {
    json["errors"] = record->errors;
  }
  return json;
}

}  // namespace softbench
