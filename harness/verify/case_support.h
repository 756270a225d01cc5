// SPDX-License-Identifier: MIT
// What the verification cases share: the models' parameters for a case, the settling run, the
// judging and the timing. Internal to harness/verify/.
#pragma once

#include "geometry/tet_mesh.h"
#include "harness/verify/verify.h"
#include "models/soft_body.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <chrono>
#include <memory>
#include <span>
#include <string>
#include <utility>

namespace softbench::harness::verify_detail {

/// The model's parameters for a case that compares with a material law: model.params over the
/// parameters its registry entry names for a stiffness that follows the material
/// (stiffness_axis.fixed_params, when the axis is the material's E).
nlohmann::json material_params(const ModelUnderTest& model);
/// material_params plus the model's settling damping where they set none (or zero): for a case
/// that only wants the static equilibrium, which the damping does not move.
nlohmann::json static_params(const ModelUnderTest& model);
/// "" for a model whose stiffness follows the material's E; else a note that an analytic
/// elastic solution is not what it is made to match.
std::string material_law_note(const std::string& model);

std::unique_ptr<SoftBody> build(const ModelUnderTest& model,
                                const TetMesh& mesh,
                                const Material& material,
                                const nlohmann::json& params,
                                const std::string& case_name);

struct SettleOutcome {
  bool stable = true;
  bool settled = false;
  bool timed_out = false;
  int steps = 0;
  std::string failure;  ///< why it stopped early when not stable or timed out
};

/// Steps the body under `constraints` and `gravity` at settings.dt until every free vertex has
/// been slower than settings.settle_speed diagonals per second for settings.settle_steps steps,
/// for at most settings.max_settle_steps steps and settings.max_wall_seconds; judges each step
/// with the one divergence rule (RunMonitor).
SettleOutcome settle(SoftBody& body,
                     const TetMesh& mesh,
                     std::span<const PositionConstraint> constraints,
                     const Eigen::Vector3d& gravity,
                     const VerifySettings& settings);

/// The case's status from its judged measures (every one within tolerance: pass; none judged:
/// not applicable), unless the case already failed or was set not applicable.
void judge(CaseResult& result);
/// Appends `note` to the case's note.
void add_note(CaseResult& result, const std::string& note);
/// A run that blew up fails the case (false: measure nothing); one that timed out or did not
/// settle is measured where it stopped, with a note saying so (true).
/// `what` (e.g. "level 2") starts the note when the case runs several simulations.
bool record_outcome(CaseResult& result, const SettleOutcome& outcome, const std::string& what = "");

/// The 10 x 6 x 4 cm box in 2 cm cells the free spin, rigid motion and squash cases use.
const TetMesh& spin_box();

/// One OpenMP thread while it lives (the previous count restored after). The cases' meshes are
/// small (at most a few thousand vertices): the models' parallel loops would mostly wait for
/// each other, and on a loaded machine for other processes (measured: the Hertz press on
/// corotational_fem took 3 s on one thread and over 60 s on two beside another busy process).
/// The models' results are the same on any thread count.
class OneThread {
 public:
  OneThread();
  ~OneThread();
  OneThread(const OneThread&) = delete;
  OneThread& operator=(const OneThread&) = delete;

 private:
  int threads_;
};

/// Seconds since construction.
class Stopwatch {
 public:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// What every case does around its measurement: one thread and a stopwatch while it lives, the
/// case's name on its result; finish() judges the result and stamps its time.
class CaseRun {
 public:
  explicit CaseRun(std::string name) { result.name = std::move(name); }
  double seconds() const { return watch_.seconds(); }
  CaseResult finish() {
    judge(result);
    result.seconds = watch_.seconds();
    return std::move(result);
  }

 private:
  OneThread one_thread_;
  Stopwatch watch_;

 public:
  CaseResult result;  ///< filled by the case
};

/// A short number for notes: 3 significant digits.
std::string short_number(double value);

}  // namespace softbench::harness::verify_detail
