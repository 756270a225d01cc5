// SPDX-License-Identifier: MIT
#pragma once

#include "models/calibration_record.h"
#include "models/json_reader.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace softbench {

/// One documented parameter, as `softbench models` lists it.
struct ParameterDoc {
  std::string name;
  nlohmann::json default_value;
  std::string description;  ///< unit, allowed values, and which way the trade-off goes
};

/// A model's parameters declared once, field by field: the same table reads them from a scene
/// (rejecting unknown keys, wrong types and values out of range), echoes the effective values
/// into reports, and documents them with their defaults. `Params` is a struct whose default
/// member initialisers are the defaults.
template <class Params>
class ParamTable {
 public:
  ParamTable& number(std::string name, double Params::*field, Range range, std::string doc) {
    add(
        std::move(name), std::move(doc),
        [field, range](const JsonReader& in, const std::string& key, Params& params) {
          params.*field = in.number_or(key, params.*field, range);
        },
        [field](const Params& params) { return nlohmann::json(params.*field); });
    return *this;
  }

  ParamTable& integer(std::string name, int Params::*field, int lo, int hi, std::string doc) {
    add(
        std::move(name), std::move(doc),
        [field, lo, hi](const JsonReader& in, const std::string& key, Params& params) {
          params.*field = in.integer_or(key, params.*field, lo, hi);
        },
        [field](const Params& params) { return nlohmann::json(params.*field); });
    return *this;
  }

  ParamTable& boolean(std::string name, bool Params::*field, std::string doc) {
    add(
        std::move(name), std::move(doc),
        [field](const JsonReader& in, const std::string& key, Params& params) {
          params.*field = in.boolean_or(key, params.*field);
        },
        [field](const Params& params) { return nlohmann::json(params.*field); });
    return *this;
  }

  /// An enum given as a string in the scene: `options` maps each spelling to its value.
  template <class Enum>
  ParamTable& choice(std::string name,
                     Enum Params::*field,
                     std::vector<std::pair<std::string, Enum>> options,
                     std::string doc) {
    add(
        std::move(name), std::move(doc),
        [field, options](const JsonReader& in, const std::string& key, Params& params) {
          const nlohmann::json* value = in.find(key);
          if (value == nullptr) {
            return;
          }
          for (const auto& [spelling, option] : options) {
            if (value->is_string() && value->get<std::string>() == spelling) {
              params.*field = option;
              return;
            }
          }
          std::string expected = "one of";
          for (const auto& option : options) {
            expected += (&option == &options.front() ? " \"" : ", \"") + option.first + "\"";
          }
          in.fail_expected(key, expected);
        },
        [field, options](const Params& params) {
          for (const auto& [spelling, option] : options) {
            if (params.*field == option) {
              return nlohmann::json(spelling);
            }
          }
          return nlohmann::json(nullptr);
        });
    return *this;
  }

  /// The record of a fit (`softbench calibrate`): null, or what the block was fitted to. Only a
  /// model whose stiffness is not a material constant has one.
  ParamTable& record(std::string name,
                     std::optional<CalibrationRecord> Params::*field,
                     std::string doc) {
    add(
        std::move(name), std::move(doc),
        [field](const JsonReader& in, const std::string& key, Params& params) {
          params.*field = read_calibration_record(in, key);
        },
        [field](const Params& params) { return softbench::to_json(params.*field); });
    return *this;
  }

  /// The parameters in `json` (an object; null means all defaults), checked against the table.
  /// `source` and `pointer` locate the block in its scene for messages.
  Params read(const nlohmann::json& json,
              const std::string& source,
              const std::string& pointer) const {
    Params params;
    if (json.is_null()) {
      return params;
    }
    const JsonReader in(json, source, pointer);
    for (const Entry& entry : entries_) {
      entry.read(in, entry.name, params);
    }
    in.reject_unknown_keys();
    return params;
  }

  nlohmann::json to_json(const Params& params) const {
    nlohmann::json json = nlohmann::json::object();
    for (const Entry& entry : entries_) {
      json[entry.name] = entry.write(params);
    }
    return json;
  }

  std::vector<ParameterDoc> docs() const {
    const Params defaults;
    std::vector<ParameterDoc> result;
    for (const Entry& entry : entries_) {
      result.push_back({entry.name, entry.write(defaults), entry.doc});
    }
    return result;
  }

 private:
  struct Entry {
    std::string name;
    std::string doc;
    std::function<void(const JsonReader&, const std::string&, Params&)> read;
    std::function<nlohmann::json(const Params&)> write;
  };

  void add(std::string name,
           std::string doc,
           std::function<void(const JsonReader&, const std::string&, Params&)> read,
           std::function<nlohmann::json(const Params&)> write) {
    entries_.push_back({std::move(name), std::move(doc), std::move(read), std::move(write)});
  }

  std::vector<Entry> entries_;
};

}  // namespace softbench
