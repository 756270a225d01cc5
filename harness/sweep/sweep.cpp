// SPDX-License-Identifier: MIT
#include "harness/sweep/sweep.h"

#include "geometry/atomic_file.h"
#include "geometry/input_error.h"
#include "geometry/text_format.h"
#include "harness/format.h"
#include "harness/provenance.h"
#include "models/model_registry.h"
#include "models/json_file.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <ostream>
#include <sstream>

namespace softbench::harness {
namespace {


std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) {
    parts.push_back(part);
  }
  return parts;
}

// "1/60" -> 0.01666..., "3000" -> 3000, "true" -> true, anything else a string.
nlohmann::json parse_value(const std::string& text) {
  if (text == "true" || text == "false") {
    return text == "true";
  }
  const auto number = [](const std::string& s) -> std::optional<double> {
    std::size_t used = 0;
    try {
      const double value = std::stod(s, &used);
      return used == s.size() ? std::optional<double>(value) : std::nullopt;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  };
  const std::vector<std::string> fraction = split(text, '/');
  if (fraction.size() == 2) {
    const auto top = number(fraction[0]);
    const auto bottom = number(fraction[1]);
    if (top && bottom && *bottom != 0.0) {
      return *top / *bottom;
    }
  }
  if (const auto value = number(text)) {
    // Integers stay integers: integer parameters reject 10.0.
    return *value == std::floor(*value) && std::abs(*value) < 1e15
               ? nlohmann::json(static_cast<long long>(*value))
               : nlohmann::json(*value);
  }
  return text;
}

double finite_or_infinity(const nlohmann::json& json) {
  return json.is_null() ? kInfinity : json.get<double>();
}

SweepRecord run_point(const scenes::Scene& scene,
                      const SceneMesh& mesh,
                      const SweepPoint& point,
                      const ReferenceRun& reference) {
  scenes::Scene varied = scene;
  varied.dt = point.dt;
  nlohmann::json settings = point.settings;
  settings.erase("dt");  // the scene's, set above
  varied.override_parameters(point.model, settings);
  RunOptions options;
  options.models = {point.model};
  options.snapshot_times = reference.times;
  const ModelRun run = run_scene(varied, mesh, options).front();
  SweepRecord record;
  record.point = point;
  record.stable = run.stability.stable;
  record.steps_per_second =
      scene.instrument ? run.timing.steps_per_second_with_collision : run.timing.steps_per_second;
  record.accuracy = accuracy_against(run.snapshots, run.contact.peak_tool_force, reference,
                                     mesh.body.rest_positions());
  record.provenance = to_json(provenance());
  return record;
}

}  // namespace

SweepAxis parse_sweep_axis(const std::string& argument) {
  const std::size_t equals = argument.find('=');
  const std::size_t dot = argument.find('.');
  if (equals == std::string::npos || dot == std::string::npos || dot > equals || dot == 0
      || equals == dot + 1 || equals + 1 == argument.size()) {
    throw InputError("--param " + argument + ": expected model.key=v1,v2,... (e.g. model.dt=1/30,1/60 "
                     "or shape_matching.clusters=1,10,50)");
  }
  SweepAxis axis;
  axis.model = argument.substr(0, dot);
  axis.key = argument.substr(dot + 1, equals - dot - 1);
  for (const std::string& value : split(argument.substr(equals + 1), ',')) {
    if (value.empty()) {
      throw InputError("--param " + argument + ": empty value");
    }
    axis.values.push_back(parse_value(value));
  }
  if (axis.key == "dt") {
    for (const nlohmann::json& value : axis.values) {
      if (!value.is_number() || value.get<double>() <= 0.0) {
        throw InputError("--param " + argument + ": dt values must be numbers > 0");
      }
    }
  }
  return axis;
}

std::vector<SweepPoint> sweep_grid(const scenes::Scene& scene,
                                   const std::string& mesh_hash,
                                   const std::vector<SweepAxis>& axes,
                                   const std::vector<std::string>& models,
                                   const std::string& reference_model) {
  std::vector<std::string> names = models;
  if (names.empty()) {  // every model a run runs, less the reference (named, it is swept too)
    for (const std::string& name : builtin_models().default_names()) {
      if (name != reference_model) {
        names.push_back(name);
      }
    }
  }
  for (const SweepAxis& axis : axes) {
    if (axis.model != "model" && std::find(names.begin(), names.end(), axis.model) == names.end()) {
      throw InputError("--param " + axis.model + "." + axis.key + ": " + axis.model
                       + " is not among the swept models");
    }
  }
  // The id names everything the result depends on: scene, mesh content, build, model, settings.
  const std::string scene_key =
      scenes::to_json(scene).dump() + "\n" + mesh_hash + "\n" + build_fingerprint();
  std::vector<SweepPoint> points;
  for (const std::string& name : names) {
    std::vector<nlohmann::json> grid = {nlohmann::json::object()};
    for (const SweepAxis& axis : axes) {
      if (axis.model != "model" && axis.model != name) {
        continue;
      }
      std::vector<nlohmann::json> next;
      for (const nlohmann::json& settings : grid) {
        for (const nlohmann::json& value : axis.values) {
          nlohmann::json extended = settings;
          extended[axis.key] = value;
          next.push_back(extended);
        }
      }
      grid = std::move(next);
    }
    for (const nlohmann::json& settings : grid) {
      SweepPoint point;
      point.model = name;
      point.settings = settings;
      point.dt = settings.contains("dt") ? settings["dt"].get<double>() : scene.dt;
      // The loader bounds the scene's own dt; a swept dt must meet the same step limit.
      const double steps = scenes::step_count(scene.duration, point.dt);
      if (steps > scenes::kMaxSteps) {
        throw InputError("--param model.dt: dt = " + format_number(point.dt) + " s is "
                         + format_number(steps, 3) + " steps of the scene's "
                         + format_number(scene.duration) + " s, over the limit of "
                         + std::to_string(scenes::kMaxSteps));
      }
      point.id = stable_hash(scene_key + "\n" + name + "\n" + settings.dump());
      points.push_back(point);
    }
  }
  return points;
}

nlohmann::json to_json(const SweepRecord& record) {
  const Accuracy& a = record.accuracy;
  return {{"id", record.point.id},
          {"model", record.point.model},
          {"dt", record.point.dt},
          {"settings", record.point.settings},
          {"stable", record.stable},
          {"steps_per_second", record.steps_per_second},
          // Simulated seconds per wall second: what a smaller dt costs in real time.
          {"realtime_factor", record.steps_per_second * record.point.dt},
          {"rms_error", number_or_null(a.rms_error)},
          {"max_error", number_or_null(a.max_error)},
          {"volume_error", number_or_null(a.volume_error)},
          {"peak_force_error",
           a.peak_force_error ? number_or_null(*a.peak_force_error) : nlohmann::json(nullptr)},
          {"provenance", record.provenance}};
}

SweepRecord sweep_record_from_json(const nlohmann::json& json, const std::string& where) {
  try {
    SweepRecord record;
    record.point.id = json.at("id").get<std::string>();
    // The id names the file merge writes (runs/<id>.json): from a file given on the command
    // line it must be a name, not a path ("../../x").
    const std::string& id = record.point.id;
    if (id.empty() || id.size() > 64 || !std::all_of(id.begin(), id.end(), [](char c) {
          return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
        })) {
      throw InputError(where + ": /id: expected a run id (letters, digits, '_' or '-'), got "
                       + json.at("id").dump());
    }
    record.point.model = json.at("model").get<std::string>();
    record.point.dt = json.at("dt").get<double>();
    record.point.settings = json.at("settings");
    record.stable = json.at("stable").get<bool>();
    record.steps_per_second = json.at("steps_per_second").get<double>();
    record.accuracy.rms_error = finite_or_infinity(json.at("rms_error"));
    record.accuracy.max_error = finite_or_infinity(json.at("max_error"));
    record.accuracy.volume_error = finite_or_infinity(json.at("volume_error"));
    record.provenance = json.value("provenance", nlohmann::json(nullptr));
    if (!json.at("peak_force_error").is_null()) {
      record.accuracy.peak_force_error = json.at("peak_force_error").get<double>();
    }
    return record;
  } catch (const nlohmann::json::exception& error) {
    throw InputError(where + ": not a sweep run record: " + error.what());
  }
}

void write_sweep_record(const std::filesystem::path& out_dir, const SweepRecord& record) {
  std::filesystem::create_directories(out_dir / "runs");
  const std::string text = to_json(record).dump(2) + "\n";
  write_file_atomically(out_dir / "runs" / (record.point.id + ".json"),
                        [&](std::ostream& out) { out << text; });
}

std::vector<SweepRecord> read_sweep_runs(const std::vector<std::filesystem::path>& dirs) {
  std::map<std::string, SweepRecord> by_id;
  for (const std::filesystem::path& dir : dirs) {
    const std::filesystem::path runs = dir / "runs";
    if (!std::filesystem::is_directory(runs)) {
      throw InputError(dir.string() + ": no runs/ folder (not a sweep output folder)");
    }
    for (const auto& entry : std::filesystem::directory_iterator(runs)) {
      if (entry.path().extension() == ".json") {
        SweepRecord record =
            sweep_record_from_json(read_json_file(entry.path(), "sweep run record"),
                                   entry.path().string());
        by_id.emplace(record.point.id, std::move(record));
      }
    }
  }
  std::vector<SweepRecord> records;
  for (auto& [id, record] : by_id) {
    records.push_back(std::move(record));
  }
  std::sort(records.begin(), records.end(), [](const SweepRecord& a, const SweepRecord& b) {
    return std::tie(a.point.model, a.point.dt, a.point.id)
           < std::tie(b.point.model, b.point.dt, b.point.id);
  });
  return records;
}

SweepResult run_sweep(const scenes::Scene& scene, const SweepOptions& options) {
  if (options.shards < 1 || options.shard < 0 || options.shard >= options.shards) {
    throw InputError("--shard: expected i/N with 0 <= i < N");
  }
  const SceneMesh mesh = read_scene_mesh(scene);
  const std::vector<SweepPoint> points =
      sweep_grid(scene, mesh.content_hash, options.axes, options.models, options.reference.model);
  const std::filesystem::path reference_dir =
      options.reference_dir.empty() ? options.out_dir / "reference" : options.reference_dir;
  const ReferenceRun reference = reference_run(scene, mesh, options.reference, reference_dir);
  ReferenceConvergence convergence;
  if (!options.trust_reference) {
    convergence =
        reference_convergence(scene, mesh, options.reference, reference_dir, reference);
  }
  write_reference_convergence(options.out_dir, convergence);
  if (options.reference_only) {
    return {{}, convergence};
  }
  const std::filesystem::path runs = options.out_dir / "runs";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SweepPoint& point = points[i];
    const std::filesystem::path file = runs / (point.id + ".json");
    if (static_cast<int>(i % static_cast<std::size_t>(options.shards)) != options.shard
        || std::filesystem::exists(file)) {
      continue;  // another shard's, or already run
    }
    const SweepRecord record = run_point(scene, mesh, point, reference);
    write_sweep_record(options.out_dir, record);
    if (options.progress != nullptr) {
      *options.progress << point.model << " " << point.settings.dump() << ": "
                        << record.steps_per_second << " steps/s, error "
                        << record.accuracy.rms_error << "\n";
    }
  }
  return {read_sweep_runs({options.out_dir}), convergence};
}

void write_reference_convergence(const std::filesystem::path& dir,
                                 const ReferenceConvergence& convergence) {
  std::filesystem::create_directories(dir);
  const std::string text = to_json(convergence).dump(2) + "\n";
  write_file_atomically(dir / kReferenceConvergenceFile, [&](std::ostream& out) { out << text; });
}

ReferenceConvergence read_reference_convergence(const std::vector<std::filesystem::path>& dirs) {
  for (const std::filesystem::path& dir : dirs) {
    const std::filesystem::path file = dir / kReferenceConvergenceFile;
    if (std::filesystem::exists(file)) {
      return reference_convergence_from_json(read_json_file(file.string()), file.string());
    }
  }
  return {};
}

std::vector<SweepRecord> pareto_front(const std::vector<SweepRecord>& records) {
  std::vector<SweepRecord> front;
  for (const SweepRecord& candidate : records) {
    if (!candidate.stable || !std::isfinite(candidate.accuracy.rms_error)) {
      continue;
    }
    const bool beaten = std::any_of(records.begin(), records.end(), [&](const SweepRecord& other) {
      return other.stable && other.point.model == candidate.point.model
             && other.steps_per_second >= candidate.steps_per_second
             && other.accuracy.rms_error <= candidate.accuracy.rms_error
             && (other.steps_per_second > candidate.steps_per_second
                 || other.accuracy.rms_error < candidate.accuracy.rms_error);
    });
    if (!beaten) {
      front.push_back(candidate);
    }
  }
  return front;
}

std::optional<SweepRecord> fastest_within(const std::vector<SweepRecord>& records, double budget) {
  std::optional<SweepRecord> best;
  for (const SweepRecord& record : records) {
    if (record.stable && record.accuracy.rms_error <= budget
        && (!best || record.steps_per_second > best->steps_per_second)) {
      best = record;
    }
  }
  return best;
}

void write_sweep_table(const std::filesystem::path& out_dir,
                       const std::string& scene_name,
                       const std::vector<SweepRecord>& records,
                       const ReferenceConvergence& convergence) {
  const std::string refusal = ranking_refusal(convergence);
  nlohmann::json json = {{"scene", scene_name},
                         {"reference_convergence", to_json(convergence)},
                         {"ranking_refused", refusal.empty() ? nlohmann::json(nullptr)
                                                             : nlohmann::json(refusal)},
                         {"records", nlohmann::json::array()},
                         {"pareto", nlohmann::json::array()},
                         {"fastest_within", nlohmann::json::object()}};
  for (const SweepRecord& record : records) {
    json["records"].push_back(to_json(record));
  }
  const std::vector<SweepRecord> ranked =
      refusal.empty() ? pareto_front(records) : std::vector<SweepRecord>{};
  for (const SweepRecord& record : ranked) {
    json["pareto"].push_back(record.point.id);
  }
  for (const double budget : {0.01, 0.05, 0.2}) {
    const std::optional<SweepRecord> best =
        refusal.empty() ? fastest_within(records, budget) : std::nullopt;
    json["fastest_within"][std::to_string(static_cast<int>(std::lround(100 * budget))) + "%"] =
        best ? to_json(*best) : nlohmann::json(nullptr);
  }
  // Header and rows from one list of record keys, so a column added to to_json(SweepRecord)
  // cannot shift the others. Settings are one quoted cell (with ' for ").
  constexpr std::array<const char*, 11> kColumns = {"id",
                                                    "model",
                                                    "dt",
                                                    "settings",
                                                    "stable",
                                                    "steps_per_second",
                                                    "realtime_factor",
                                                    "rms_error",
                                                    "max_error",
                                                    "volume_error",
                                                    "peak_force_error"};
  std::ostringstream csv;
  for (std::size_t c = 0; c < kColumns.size(); ++c) {
    csv << (c > 0 ? "," : "") << kColumns[c];
  }
  csv << "\n";
  for (const SweepRecord& record : records) {
    const nlohmann::json row = to_json(record);
    for (std::size_t c = 0; c < kColumns.size(); ++c) {
      const nlohmann::json& cell = row.at(kColumns[c]);
      std::string text = cell.is_string() ? cell.get<std::string>() : cell.dump();
      if (cell.is_object()) {
        std::replace(text.begin(), text.end(), '"', '\'');
        text = "\"" + text + "\"";
      }
      csv << (c > 0 ? "," : "") << text;
    }
    csv << "\n";
  }
  std::filesystem::create_directories(out_dir);
  const std::string text = json.dump(2) + "\n";
  write_file_atomically(out_dir / "sweep.json", [&](std::ostream& out) { out << text; });
  const std::string table = csv.str();
  write_file_atomically(out_dir / "sweep.csv", [&](std::ostream& out) { out << table; });
}

}  // namespace softbench::harness
