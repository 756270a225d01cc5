// SPDX-License-Identifier: MIT
#pragma once

#include "harness/run/scene_mesh.h"
#include "models/soft_body.h"
#include "scenes/scene.h"
#include "viewer/hand_tool.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace softbench::viewer {

/// Who moves the instrument: the user's hand (ToolCommand), or the scene's script from t = 0.
enum class Drive { kHand, kScript };

/// What the window draws of one model, copied out under a lock.
struct LiveFrame {
  Eigen::Matrix3Xd positions;  ///< 3 x #V, m
  bool tool_visible = false;
  Eigen::Isometry3d tool_pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d tool_force = Eigen::Vector3d::Zero();  ///< N, the tissue on the tool
  std::vector<int> contacts;  ///< vertices the instrument holds this step
  double time = 0.0;          ///< s of simulated time
  long long steps = 0;
  double steps_per_second = 0.0;  ///< over the last second of wall time
  /// Simulated seconds per wall second over the last second, while playing (1: real time).
  double real_time = 0.0;
  double step_ms = 0.0;  ///< median wall time of the last 60 steps (contact passes included)
  bool playing = false;
  bool ended = false;  ///< the scene's script has run to its end
  bool grasping = false;
  Drive drive = Drive::kHand;
  std::string failure;  ///< why the body stopped (diverged), or ""
  nlohmann::json parameters;  ///< the body's effective parameters
};

/// One model of a scene, simulated on a thread of its own at the scene's dt, paced to wall time:
/// rendering never slows the physics (the window takes the latest frame, dropping frames, not
/// steps), and a model that cannot keep up is stepped as fast as it can, its frame saying how
/// far behind it runs. The instrument is the scene's, moved by the hand (Drive::kHand: the
/// scene's gravity, fixed region and supports, the scripted grasp and path left out) or by the
/// scene's script, through the same loading and contact code as every command
/// (harness::SceneStepper).
class LiveModel {
 public:
  /// `scene` must have an instrument and `mesh` its mesh (harness::read_scene_mesh). Throws
  /// InputError for a bad parameter block of `model`.
  LiveModel(const scenes::Scene& scene, const harness::SceneMesh& mesh, std::string model);
  ~LiveModel();
  LiveModel(const LiveModel&) = delete;
  LiveModel& operator=(const LiveModel&) = delete;

  const std::string& model() const { return model_; }
  void command(const ToolCommand& command);
  void play(bool playing);
  void step_once();  ///< one step, when paused
  /// Back to the rest shape at t = 0, driven by `drive`.
  void reset(Drive drive);
  /// Rebuilds the body from `block` (the model's parameters, merged over the scene's) and
  /// resets it. Returns the parameter error (the body is kept) or "".
  std::string set_parameters(const nlohmann::json& block);
  LiveFrame frame() const;

 private:
  void run();
  void restart(Drive drive);  ///< sim thread: a fresh stepper on the chosen scene, t = 0
  void take_step();           ///< sim thread
  void publish(double step_seconds);

  const scenes::Scene& scene_;    ///< as loaded: the script
  scenes::Scene hand_scene_;      ///< the hand's: its instrument path rewritten step by step
  const harness::SceneMesh& mesh_;
  const std::string model_;

  // Shared with the window, under mutex_.
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  ToolCommand command_;
  std::unique_ptr<SoftBody> pending_body_;
  bool reset_requested_ = true;
  Drive requested_drive_ = Drive::kHand;
  bool playing_ = true;
  int steps_requested_ = 0;
  bool quit_ = false;
  LiveFrame frame_;

  // The sim thread's own.
  std::unique_ptr<SoftBody> body_;
  struct Stepping;
  std::unique_ptr<Stepping> stepping_;
  std::thread thread_;
};

}  // namespace softbench::viewer
