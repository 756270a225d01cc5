// SPDX-License-Identifier: MIT
#include "harness/claim.h"

#include "geometry/input_error.h"

#include <cctype>

namespace softbench::harness {

std::string_view to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::kPass:
      return "pass";
    case Verdict::kFail:
      return "fail";
    case Verdict::kObserved:
      return "observed";
    case Verdict::kNotObserved:
      return "not observed";
    case Verdict::kNotRun:
      return "not run";
  }
  return "not run";
}

Verdict verdict_from_string(std::string_view text) {
  for (const Verdict verdict : {Verdict::kPass, Verdict::kFail, Verdict::kObserved,
                                Verdict::kNotObserved, Verdict::kNotRun}) {
    if (to_string(verdict) == text) {
      return verdict;
    }
  }
  throw InputError("unknown verdict \"" + std::string(text)
                   + "\" (expected pass, fail, observed, not observed or not run)");
}

std::string verdict_badge(Verdict verdict) {
  std::string text(to_string(verdict));
  for (char& c : text) {
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return "**" + text + "**";
}

nlohmann::json to_json(const Claim& claim) {
  return {{"id", claim.id},
          {"claim", claim.claim},
          {"criterion", claim.criterion},
          {"verdict", to_string(claim.verdict)},
          {"evidence", claim.evidence}};
}

Claim claim_from_json(const JsonReader& in) {
  Claim claim;
  claim.id = in.string("id");
  claim.claim = in.string("claim");
  claim.criterion = in.string("criterion");
  try {
    claim.verdict = verdict_from_string(in.string("verdict"));
  } catch (const InputError& error) {
    in.fail("verdict", error.what());
  }
  claim.evidence = in.string("evidence");
  return claim;
}

std::string claim_markdown(const Claim& claim) {
  return "- " + verdict_badge(claim.verdict) + " " + claim.claim
         + "\n  - criterion: " + claim.criterion + "\n  - evidence: " + claim.evidence + "\n";
}

}  // namespace softbench::harness
