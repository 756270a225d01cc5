// SPDX-License-Identifier: MIT
#pragma once

#include "models/material.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace softbench::scenes {

// A scene as plain data: what scenes/README.md documents, after validation and with defaults
// filled in. SI units throughout (m, s, kg, Pa, N). Only scenes/ and each model's parameter
// table see JSON; everything else works on these structs.

inline constexpr double kNever = std::numeric_limits<double>::infinity();

/// The most time steps a scene may take (duration / dt). Runs size per-step records by it, so a
/// dt of 1e-300 would otherwise ask for more memory than exists (and overflow num_steps()'s
/// int); the loader rejects a scene over it before anything is allocated. 10 million is
/// 46 hours of scene time at the thesis's 1/60 s.
inline constexpr int kMaxSteps = 10'000'000;
/// ceil(duration / dt) as a double, so it can be compared with kMaxSteps before it becomes an
/// int (1e9 s at dt = 1e-300 is infinite).
double step_count(double duration, double dt);

struct Box {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
};

struct Plane {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  ///< unit length after loading
  double tolerance = 0.0;  ///< m: vertices within this distance of the plane are selected
};

/// The vertices held in place for the whole scene: the union of an explicit list, a box and a
/// plane band (any of them may be absent). A region that selects nothing, or none at all, is a
/// free body.
struct FixedRegion {
  std::vector<int> vertices;
  std::optional<Box> box;
  std::optional<Plane> plane;
};

/// The body's velocity at t = 0, a rigid motion of its rest shape: vertex i (at rest position
/// x_i) starts at v_i = linear + angular x (x_i - center). Vertices held by the fixed region
/// start at rest.
struct InitialVelocity {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   ///< m/s
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  ///< rad/s
  /// m; absent: the body's centre of mass at rest (known only with the mesh:
  /// scenes::initial_velocities).
  std::optional<Eigen::Vector3d> center;
};

/// Gravity, switched off at `off_at` (the liver_gravity scene's "release").
struct Gravity {
  Eigen::Vector3d acceleration{0.0, 0.0, -9.81};  ///< m/s^2
  double off_at = kNever;                         ///< s
};

/// A grasp path keyframe: displacement of the grasped patch from where it was grasped.
struct GraspKeyframe {
  double time = 0.0;                                 ///< s, absolute scene time
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< m
};

/// A patch of surface vertices (those within `radius` of `center` at rest) held from
/// `start`, moved along `path` (piecewise linear in time; constant after the last keyframe),
/// and let go at `release`.
struct Grasp {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< m, in the rest frame
  double radius = 0.01;                              ///< m
  double start = 0.0;                                ///< s
  double release = kNever;                           ///< s
  std::vector<GraspKeyframe> path;                   ///< times in [start, release], increasing
};

/// An instrument keyframe: the pose of the instrument mesh's own frame in the world at `time`.
/// Between keyframes the position moves linearly and the orientation by slerp; before the first
/// and after the last the pose holds.
struct InstrumentKeyframe {
  double time = 0.0;                                   ///< s
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< m, where the mesh's origin goes
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< mesh frame -> world
};

/// The instrument closes on the tissue: at `start` the boundary-surface vertices within `radius`
/// of `center` at rest attach to the instrument where they are then, and move with it rigidly
/// until `release`.
struct InstrumentGrasp {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< m, rest frame
  double radius = 0.01;                              ///< m
  double start = 0.0;                                ///< s
  double release = kNever;                           ///< s
};

/// Instrument::contact_passes's default.
inline constexpr int kDefaultContactPasses = 32;
/// The most contact passes a scene may ask for (each is a whole step of the model).
inline constexpr int kMaxContactPasses = 1000;

/// A rigid instrument (a closed triangle mesh) moved along a scripted path. Tissue vertices that
/// end up inside it are projected to its surface; instrument vertices that end up inside the
/// tissue push the tissue's surface triangle out of the way (collision/instrument_contact.h).
struct Instrument {
  std::filesystem::path mesh;            ///< resolved against the scene file's folder
  std::vector<InstrumentKeyframe> path;  ///< times increasing
  std::optional<InstrumentGrasp> grasp;
  /// s: when the instrument begins to act on the tissue; the shape recovery is measured
  /// against is taken then.
  double start = 0.0;
  /// s: when it lets go (starts to withdraw); recovery is measured from then. The grasp's
  /// release when there is a grasp.
  double release = kNever;
  /// m: gap kept between tissue and instrument; contact holds while they are closer. Small
  /// against the mesh's edges, large against rounding.
  double contact_margin = 2e-4;
  /// The most passes of a step: the first and the contact's active-set corrections (a pass adds
  /// or drops holds, and the step is taken again from its start). Most steps settle in one or
  /// two; a step that runs out of passes keeps its last pass with its holds still changing
  /// (counted: ContactMetrics::unsettled_steps), and the tool may end inside the tissue.
  /// Measured on liver_press: corotational_fem and bullet_softbody end the same with a cap of 4
  /// or 32; shape matching and the mass-spring model need up to 7 passes on a few dozen steps
  /// and 21-25 on one or two (their unheld neighbours fold over the probe's tip and are held in
  /// turn). With 4 passes shape matching ended 1.78 mm inside the probe and mass_spring 1.50
  /// mm, with 8 passes 1.17 mm, with 32 none; steps that settle early cost the same, so the cap
  /// only bounds the worst step (a haptic loop's budget: fewer passes, a bounded step, and the
  /// unsettled steps reported).
  int contact_passes = kDefaultContactPasses;
};

/// When a run counts as blown up. A diverged model is reported, and the run goes on with the
/// next model.
struct StabilityLimits {
  double max_speed = 50.0;  ///< m/s; faster than any tissue in these scenes moves
  /// Largest displacement from rest as a multiple of the rest bounding-box diagonal.
  double max_displacement = 10.0;
};

/// What a user needs from the scene's runs (optional): `softbench recommend` picks the cheapest
/// model and settings that meet it, and a run computes the reference only when an accuracy is
/// asked for.
struct Requirements {
  double steps_per_second = 0.0;   ///< the frame budget; 0: none
  std::optional<double> accuracy;  ///< largest relative RMS position error vs the reference
  /// What the user reads: "surface" (positions), "volume", "contact_force". Each named output
  /// must be within the accuracy too.
  std::vector<std::string> outputs = {"surface"};
};

struct Scene {
  std::string name;
  std::string description;
  std::filesystem::path source;  ///< the scene file
  std::filesystem::path mesh;    ///< resolved against the scene file's folder
  Material material;
  Gravity gravity;
  double dt = 1.0 / 60.0;  ///< s
  double duration = 1.0;   ///< s
  FixedRegion fixed;
  /// Frictionless supports: the vertices within each plane's tolerance at rest stay on the plane
  /// and slide freely in it (a table under the body, a symmetry plane of a half or quarter
  /// model). A fixed vertex stays fixed.
  std::vector<Plane> supports;
  std::optional<InitialVelocity> initial_velocity;  ///< absent: the body starts at rest
  std::optional<Grasp> grasp;
  std::optional<Instrument> instrument;
  StabilityLimits limits;
  std::optional<Requirements> requirements;
  /// Per-model parameter blocks, as written; each model validates its own.
  std::map<std::string, nlohmann::json> model_parameters;
  /// `model`'s parameter block ({} where the scene has none).
  nlohmann::json parameters_for(const std::string& model) const;
  /// Merges `settings` into `model`'s block, creating it: a compare variant's or a sweep point's
  /// overrides.
  void override_parameters(const std::string& model, const nlohmann::json& settings);

  int num_steps() const;  ///< ceil(duration / dt), at most kMaxSteps once loaded
  /// s: when the loads that recovery is measured after are let go (the grasp's release, else
  /// gravity's off time); kNever if nothing is released.
  double release_time() const;
  /// s: the time whose shape recovery is measured against (just before the grasp acts; 0 when
  /// the load acts from the start, i.e. the rest shape).
  double reference_time() const;
};

/// Loads and validates a scene file. Errors name the file, the JSON pointer and what was
/// expected: `scenes/x.json: /material/poisson_ratio: expected a number in [0, 0.5), got 0.5`.
/// Checks that the mesh (and instrument mesh) files exist, but does not read them.
Scene load_scene(const std::filesystem::path& path);
/// The same from already-parsed JSON; `source` names the file and resolves relative paths.
Scene parse_scene(const nlohmann::json& json, const std::filesystem::path& source);

/// The scene with every default filled in, as JSON, for metrics.json.
nlohmann::json to_json(const Scene& scene);

}  // namespace softbench::scenes
