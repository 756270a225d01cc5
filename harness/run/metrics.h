// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_measures.h"  // count_inverted_tets, which the metrics use
#include "geometry/tet_mesh.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace softbench::harness {

/// Median, 95th percentile and maximum of a sample, in the sample's unit.
struct Percentiles {
  double median = 0.0;
  double p95 = 0.0;
  double max = 0.0;
};
/// Nearest-rank percentiles; zeros for an empty sample.
Percentiles percentiles(std::vector<double> sample);


/// RMS over vertices of |a_i - b_i| (3 x #V each), m.
double rms_distance(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b);

/// Largest vertex speed, m/s.
double max_speed(const Eigen::Matrix3Xd& velocities);

/// Kinetic energy sum 1/2 m_i |v_i|^2, J.
double kinetic_energy(const Eigen::VectorXd& masses, const Eigen::Matrix3Xd& velocities);

/// The recovery residual (RMS distance to the shape before the load / rest bounding-box diagonal)
/// below which a body counts as recovered, in every report and claim.
inline constexpr double kRecoveredResidual = 0.01;

/// Recovery after release: the residual over time, and when it fell below kRecoveredResidual for
/// good.
class RecoveryTracker {
 public:
  RecoveryTracker(double release_time, double diagonal)
      : release_(release_time), diagonal_(diagonal) {}
  /// Call after each step with the scene time at its end and the reference shape.
  void observe(double time, const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& reference);
  bool released() const { return observed_; }
  double residual() const { return residual_; }  ///< relative, at the last observation
  /// s after release from which the residual stayed below kRecoveredResidual; empty if it
  /// ended above.
  std::optional<double> time_to_one_percent() const;

 private:
  double release_;
  double diagonal_;
  bool observed_ = false;
  double residual_ = 0.0;
  std::optional<double> below_since_;
};

}  // namespace softbench::harness
