// SPDX-License-Identifier: MIT
#pragma once

#include "models/json_reader.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace softbench {

/// What a fitted parameter block was fitted to, as `softbench calibrate` writes it into the
/// block under "calibrated": the reference model, the time step the fit holds for (a unitless
/// stiffness means something else at another dt), and the reference's targets with the error
/// the fit left on each. Echoed into every report, so a reader sees the values were fitted and
/// to what. Models whose stiffness is not a material constant accept it (ParamTable::record).
struct CalibrationRecord {
  std::string against;  ///< the reference model
  double dt = 0.0;      ///< s
  double sag = 0.0;     ///< m: the reference's static sag under gravity
  /// N: the reference's press force at each of `depths` past first contact (empty: sag only).
  std::vector<double> forces;
  std::vector<double> depths;  ///< m
  /// Relative errors the fit left: on the sag, then on each force (empty when not recorded).
  std::vector<double> errors;
};

/// Reads the record at `key` of `in`: null (none) or an object {"against", "dt", "sag"
/// [, "depths", "forces", "errors"]}; anything else is an InputError naming the pointer.
std::optional<CalibrationRecord> read_calibration_record(const JsonReader& in,
                                                         const std::string& key);
nlohmann::json to_json(const std::optional<CalibrationRecord>& record);

}  // namespace softbench
