// SPDX-License-Identifier: MIT
#include "harness/sweep/recommend.h"

#include "harness/format.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace softbench::harness {
namespace {

std::string describe(const SweepRecord& record) {
  std::ostringstream out;
  out.precision(4);
  out << record.point.model << " " << record.point.settings.dump() << " (dt " << record.point.dt
      << " s): " << record.steps_per_second << " steps/s, position error "
      << percent(record.accuracy.rms_error);
  return out.str();
}

bool has(const std::vector<std::string>& outputs, const std::string& output) {
  return std::find(outputs.begin(), outputs.end(), output) != outputs.end();
}

}  // namespace

std::string shortfall(const SweepRecord& record, const scenes::Requirements& requirements) {
  if (!record.stable) {
    return "unstable";
  }
  std::vector<std::string> misses;
  if (record.steps_per_second < requirements.steps_per_second) {
    std::ostringstream out;
    out.precision(4);
    out << record.steps_per_second << " steps/s < " << requirements.steps_per_second;
    misses.push_back(out.str());
  }
  if (requirements.accuracy) {
    const double budget = *requirements.accuracy;
    const Accuracy& a = record.accuracy;
    if (has(requirements.outputs, "surface") && !(a.rms_error <= budget)) {
      misses.push_back("position error " + percent(a.rms_error) + " > " + percent(budget));
    }
    if (has(requirements.outputs, "volume") && !(a.volume_error <= budget)) {
      misses.push_back("volume error " + percent(a.volume_error) + " > " + percent(budget));
    }
    if (has(requirements.outputs, "contact_force")) {
      if (!a.peak_force_error) {
        misses.push_back("no contact force to compare (the scene has no tool)");
      } else if (!(*a.peak_force_error <= budget)) {
        misses.push_back("peak force error " + percent(*a.peak_force_error) + " > "
                         + percent(budget));
      }
    }
  }
  std::string joined;
  for (const std::string& miss : misses) {
    joined += (joined.empty() ? "" : "; ") + miss;
  }
  return joined;
}

Recommendation recommend(const scenes::Requirements& requirements,
                         const std::vector<SweepRecord>& records) {
  Recommendation result;
  std::map<std::string, std::vector<const SweepRecord*>> by_model;
  for (const SweepRecord& record : records) {
    by_model[record.point.model].push_back(&record);
    if (shortfall(record, requirements).empty()
        && (!result.choice || record.steps_per_second > result.choice->steps_per_second)) {
      result.choice = record;
    }
  }
  std::ostringstream out;
  out << "Requirements: " << requirements.steps_per_second << " steps/s or more";
  if (requirements.accuracy) {
    out << ", error at most " << percent(*requirements.accuracy) << " on";
    for (const std::string& output : requirements.outputs) {
      out << " " << output;
    }
  } else {
    out << ", no accuracy asked";
  }
  out << "; " << records.size() << " swept runs.\n\n";
  if (result.choice) {
    out << "**Choice:** " << describe(*result.choice)
        << ". It is the fastest run that meets every requirement.\n\n";
  } else {
    out << "**No run meets the requirements.** Relax the budget or the accuracy, or sweep more "
           "settings.\n\n";
  }
  out << "Per model, its fastest run that meets them, or else its most accurate run and what it "
         "misses:\n\n";
  for (const auto& [model, runs] : by_model) {
    const SweepRecord* best = nullptr;
    for (const SweepRecord* run : runs) {
      if (shortfall(*run, requirements).empty()
          && (best == nullptr || run->steps_per_second > best->steps_per_second)) {
        best = run;
      }
    }
    if (best != nullptr) {
      out << "- " << describe(*best) << ": meets them\n";
      continue;
    }
    const SweepRecord* closest =
        *std::min_element(runs.begin(), runs.end(), [](const SweepRecord* a, const SweepRecord* b) {
          return std::make_pair(!a->stable, a->accuracy.rms_error)
                 < std::make_pair(!b->stable, b->accuracy.rms_error);
        });
    out << "- " << describe(*closest) << ": " << shortfall(*closest, requirements) << "\n";
  }
  result.explanation = out.str();
  return result;
}

}  // namespace softbench::harness
