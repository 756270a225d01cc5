// SPDX-License-Identifier: MIT
#include "viewer/live_model.h"

#include "geometry/input_error.h"
#include "harness/interrupt.h"
#include "harness/run/run_monitor.h"
#include "harness/run/scene_stepper.h"
#include "models/model_registry.h"
#include "scenes/instrument_path.h"

#include <algorithm>
#include <chrono>
#include <deque>

namespace softbench::viewer {
namespace {

using Clock = std::chrono::steady_clock;

/// m: the tissue within this of the tip's point is grasped (the scenes' grasps are 1-2 cm).
constexpr double kGraspRadius = 0.008;
/// s: a model further behind wall time than this gives the debt up and goes on from now, so a
/// slow model is shown at its own pace, not racing to catch up after a stall.
constexpr double kMaxLag = 0.25;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

scenes::InstrumentKeyframe keyframe(double time, const Eigen::Isometry3d& pose) {
  scenes::InstrumentKeyframe key;
  key.time = time;
  key.position = pose.translation();
  key.orientation = Eigen::Quaterniond(pose.linear());
  return key;
}

/// The scene the hand drives: the scene's body, material, gravity, fixed region and supports,
/// and its instrument without the script (no path, no scripted grasp, acting from t = 0).
scenes::Scene hand_scene(const scenes::Scene& scene) {
  scenes::Scene hand = scene;
  hand.grasp.reset();
  hand.initial_velocity.reset();
  hand.instrument->grasp.reset();
  hand.instrument->start = 0.0;
  hand.instrument->release = scenes::kNever;
  return hand;
}

}  // namespace

/// The sim thread's state of one run from t = 0.
struct LiveModel::Stepping {
  Stepping(const scenes::Scene& scene_in,
           const harness::SceneMesh& mesh,
           Drive drive_in,
           const Eigen::Vector3d& parked)
      : scene(scene_in),
        drive(drive_in),
        stepper(std::make_unique<harness::SceneStepper>(scene_in, mesh)),
        monitor(mesh.body, scene_in.limits, mesh.diagonal()),
        hand(parked) {}

  const scenes::Scene& scene;
  Drive drive;
  std::unique_ptr<harness::SceneStepper> stepper;
  harness::RunMonitor monitor;
  HandTool hand;
  int step = 0;
  bool grasping = false;
  std::string failure;
  // Pacing: simulated time `sim_origin` was due at wall time `wall_origin`.
  Clock::time_point wall_origin = Clock::now();
  double sim_origin = 0.0;
  std::deque<double> step_seconds;  ///< the last 60 steps' wall times
  struct Sample {
    Clock::time_point wall;
    double time;
    int step;
  };
  std::deque<Sample> recent;  ///< the last second's steps, for the rates

  double time() const { return step * scene.dt; }
};

LiveModel::LiveModel(const scenes::Scene& scene, const harness::SceneMesh& mesh, std::string model)
    : scene_(scene), hand_scene_(hand_scene(scene)), mesh_(mesh), model_(std::move(model)) {
  const ModelInfo& info = builtin_models().at(model_);
  body_ = info.create(mesh_.body, scene_.material, scene_.parameters_for(model_),
                      {scene_.source.string(), "/models/" + model_});
  frame_.positions = body_->positions();
  frame_.parameters = body_->parameters();
  thread_ = std::thread([this] { run(); });
}

LiveModel::~LiveModel() {
  {
    const std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void LiveModel::command(const ToolCommand& command) {
  const std::lock_guard lock(mutex_);
  command_ = command;
}

void LiveModel::play(bool playing) {
  {
    const std::lock_guard lock(mutex_);
    playing_ = playing;
  }
  wake_.notify_all();
}

void LiveModel::step_once() {
  {
    const std::lock_guard lock(mutex_);
    ++steps_requested_;
  }
  wake_.notify_all();
}

void LiveModel::reset(Drive drive) {
  {
    const std::lock_guard lock(mutex_);
    reset_requested_ = true;
    requested_drive_ = drive;
  }
  wake_.notify_all();
}

std::string LiveModel::set_parameters(const nlohmann::json& block) {
  nlohmann::json merged = scene_.parameters_for(model_);
  merged.merge_patch(block);
  std::unique_ptr<SoftBody> body;
  try {
    body = builtin_models().at(model_).create(mesh_.body, scene_.material, merged,
                                              {"the viewer's panel", "/models/" + model_});
  } catch (const InputError& error) {
    return error.what();
  }
  {
    const std::lock_guard lock(mutex_);
    pending_body_ = std::move(body);
    reset_requested_ = true;
  }
  wake_.notify_all();
  return "";
}

LiveFrame LiveModel::frame() const {
  const std::lock_guard lock(mutex_);
  return frame_;
}

void LiveModel::restart(Drive drive) {
  body_->reset();
  // Parked far above the body: in the scene, touching nothing.
  const Eigen::Vector3d parked =
      mesh_.body.rest_positions().rowwise().mean() + 100.0 * mesh_.diagonal() * Eigen::Vector3d::UnitZ();
  const scenes::Scene& scene = drive == Drive::kScript ? scene_ : hand_scene_;
  if (drive == Drive::kHand) {
    hand_scene_ = hand_scene(scene_);
    hand_scene_.instrument->path = {keyframe(0.0, Eigen::Isometry3d(Eigen::Translation3d(parked)))};
  }
  stepping_ = std::make_unique<Stepping>(scene, mesh_, drive, parked);
  if (drive == Drive::kScript) {
    stepping_->stepper->start(*body_);
  }
}

void LiveModel::take_step() {
  Stepping& s = *stepping_;
  const double start = s.time();
  const double dt = s.scene.dt;
  if (s.drive == Drive::kHand) {
    ToolCommand command;
    {
      const std::lock_guard lock(mutex_);
      command = command_;
    }
    const Eigen::Isometry3d from = s.hand.pose();
    const Eigen::Isometry3d to = s.hand.advance(command, dt);
    const bool grasp = command.grasp && command.pressing && !s.hand.parked();
    if (grasp && !s.grasping) {
      // The tissue under the tip closes on the tool from this step: a new loading picks the
      // grasped vertices (its contact's active set starts afresh).
      hand_scene_.instrument->grasp =
          scenes::InstrumentGrasp{command.rest_point, kGraspRadius, start, scenes::kNever};
      s.stepper = std::make_unique<harness::SceneStepper>(hand_scene_, mesh_);
    } else if (!grasp && s.grasping) {
      hand_scene_.instrument->grasp->release = start;
    }
    s.grasping = grasp;
    hand_scene_.instrument->path = {keyframe(start, from), keyframe(start + dt, to)};
  }
  const Clock::time_point before = Clock::now();
  const StepStats stats = s.stepper->step(s.step, *body_);
  const double seconds = seconds_between(before, Clock::now());
  if (!s.monitor.after_step(s.step, stats, *body_, s.stepper->constraints())) {
    s.failure = "diverged at " + std::to_string(start + dt) + " s: " + s.monitor.divergence()->reason
                + " (reset to go on)";
  }
  s.stepper->observe(s.step, *body_);
  ++s.step;
  publish(seconds);
}

void LiveModel::publish(double step_seconds) {
  Stepping& s = *stepping_;
  const Clock::time_point now = Clock::now();
  if (step_seconds >= 0.0) {
    s.step_seconds.push_back(step_seconds);
    if (s.step_seconds.size() > 60) {
      s.step_seconds.pop_front();
    }
    s.recent.push_back({now, s.time(), s.step});
  }
  while (!s.recent.empty() && seconds_between(s.recent.front().wall, now) > 1.0) {
    s.recent.pop_front();
  }
  std::vector<double> sorted(s.step_seconds.begin(), s.step_seconds.end());
  std::sort(sorted.begin(), sorted.end());

  const std::lock_guard lock(mutex_);
  frame_.positions = body_->positions();
  frame_.time = s.time();
  frame_.steps = s.step;
  frame_.step_ms = sorted.empty() ? 0.0 : 1000.0 * sorted[sorted.size() / 2];
  const double span = s.recent.size() < 2 ? 0.0 : seconds_between(s.recent.front().wall, now);
  frame_.steps_per_second = span > 0.0 ? (s.recent.back().step - s.recent.front().step) / span : 0.0;
  frame_.real_time = span > 0.0 ? (s.recent.back().time - s.recent.front().time) / span : 0.0;
  frame_.ended = s.drive == Drive::kScript && s.step >= s.scene.num_steps();
  frame_.playing = playing_ && s.failure.empty() && !frame_.ended;
  frame_.grasping = s.grasping;
  frame_.drive = s.drive;
  frame_.failure = s.failure;
  frame_.parameters = body_->parameters();
  frame_.contacts.clear();
  for (const PositionConstraint& held : s.stepper->constraints()) {
    if (!held.anchors) {
      frame_.contacts.push_back(held.vertex);
    }
  }
  frame_.tool_force = s.stepper->loading().tool_force_vector();
  if (s.drive == Drive::kHand) {
    frame_.tool_visible = !s.hand.parked();
    frame_.tool_pose = s.hand.pose();
  } else {
    // A tool the script never starts (the viewer's probe on a scene without one) stays away.
    frame_.tool_visible = scene_.instrument->start < scenes::kNever;
    frame_.tool_pose = scenes::instrument_pose(*scene_.instrument, s.time());
  }
}

void LiveModel::run() {
  try {
    std::unique_lock lock(mutex_);
    while (!quit_) {
      if (pending_body_) {
        body_ = std::move(pending_body_);
      }
      if (reset_requested_) {
        reset_requested_ = false;
        const Drive drive = requested_drive_;
        lock.unlock();
        restart(drive);
        publish(-1.0);
        lock.lock();
      }
      Stepping& s = *stepping_;
      const bool finished = !s.failure.empty()
                            || (s.drive == Drive::kScript && s.step >= s.scene.num_steps());
      const bool stepping = steps_requested_ > 0 && !finished;
      if ((!playing_ || finished) && !stepping) {
        s.recent.clear();
        wake_.wait_for(lock, std::chrono::milliseconds(50));
        // Playing resumes from now: the pause is not a debt.
        s.wall_origin = Clock::now();
        s.sim_origin = s.time();
        continue;
      }
      if (!stepping) {
        const Clock::time_point now = Clock::now();
        const double due = s.sim_origin + seconds_between(s.wall_origin, now);
        const double next = s.time() + s.scene.dt;
        if (next > due) {
          // Ahead of the wall clock: wait for it (or for the window).
          wake_.wait_for(lock, std::chrono::duration<double>(std::min(next - due, 0.05)));
          continue;
        }
        if (due - s.time() > kMaxLag) {
          s.wall_origin = now;
          s.sim_origin = s.time();
        }
      } else {
        --steps_requested_;
      }
      lock.unlock();
      take_step();
      lock.lock();
    }
  } catch (const harness::Interrupted&) {
    // Ctrl-C: the window sees interrupt_requested() and closes; this thread just stops.
  }
}

}  // namespace softbench::viewer
