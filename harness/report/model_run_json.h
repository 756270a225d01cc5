// SPDX-License-Identifier: MIT
// One ModelRun as JSON, the same object in metrics.json and compare.json: a group per metrics
// struct ("timing", "stability", "shape", "recovery", "contact", "solver", "accuracy"), the
// plausibility warnings ("warnings": [{"id": ..., "message": ...}], empty when none) and the
// per-step series as columns ("series": {"time": [...], "tool_displacement": [...],
// "tool_force": [...], "recovery_residual": [...]}), null wherever a value is NaN or infinite
// (JSON has neither): the residual before the release, errors of a run that blew up.
#pragma once

#include "harness/format.h"
#include "harness/run/runner.h"
#include "models/json_reader.h"

#include <nlohmann/json.hpp>

namespace softbench::harness {

nlohmann::json to_json(const ModelRun& run);
/// The inverse of to_json() (snapshots aside: they are not written). Throws InputError naming
/// the file and JSON pointer of a missing or mistyped key.
ModelRun model_run_from_json(const JsonReader& in);

}  // namespace softbench::harness
