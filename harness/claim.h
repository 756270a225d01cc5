// SPDX-License-Identifier: MIT
// A claim of the thesis checked against measurements: the one type every report (compare,
// stability) judges, writes and reads claims with.
#pragma once

#include "models/json_reader.h"

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace softbench::harness {

/// pass/fail for a claim the thesis states as fact; observed/not observed for one it states as a
/// possibility ("may fail"), which a run can show but not refute; not run when the runs it needs
/// are missing.
enum class Verdict { kPass, kFail, kObserved, kNotObserved, kNotRun };
/// "pass", "fail", "observed", "not observed", "not run".
std::string_view to_string(Verdict verdict);
/// The inverse of to_string(); throws InputError for anything else.
Verdict verdict_from_string(std::string_view text);
/// The verdict in bold capitals, for Markdown.
std::string verdict_badge(Verdict verdict);

struct Claim {
  std::string id;         ///< stable key in the JSON reports
  std::string claim;      ///< the thesis's claim
  std::string criterion;  ///< how it is measured here
  Verdict verdict = Verdict::kNotRun;
  std::string evidence;  ///< the measured numbers behind the verdict
};

nlohmann::json to_json(const Claim& claim);
/// Reads to_json's object; throws InputError naming the file and the key.
Claim claim_from_json(const JsonReader& in);
/// "- **PASS** claim\n  - criterion: ...\n  - evidence: ...\n".
std::string claim_markdown(const Claim& claim);

}  // namespace softbench::harness
