// SPDX-License-Identifier: MIT
#include "bench/bench_liver.h"

#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "scenes/shipped_data.h"

#include <cmath>
#include <map>

namespace softbench::bench {

const TetMesh& shipped_liver(const std::string& name) {
  static std::map<std::string, TetMesh> loaded;
  auto found = loaded.find(name);
  if (found == loaded.end()) {
    found = loaded.emplace(name, make_tet_mesh(read_mesh(scenes::shipped_data_file(name)))).first;
  }
  return found->second;
}

std::vector<PositionConstraint> pin_lowest_tenth_in_x(const TetMesh& mesh) {
  const Eigen::Matrix<double, 3, 2> bounds = bounding_box(mesh.rest_positions());
  const double limit = bounds(0, 0) + 0.1 * (bounds(0, 1) - bounds(0, 0));
  std::vector<PositionConstraint> pins;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.rest_positions()(0, v) < limit) {
      pins.push_back({v, mesh.rest_positions().col(v), kExact});
    }
  }
  return pins;
}

StepInput liver_input(std::span<const PositionConstraint> pins) {
  StepInput input;
  input.gravity = {0.0, 0.0, -9.81};
  input.constraints = pins;
  return input;
}

double sag_error(const TetMesh& mesh, SoftBody& approximate, SoftBody& converged, int steps) {
  const std::vector<PositionConstraint> pins = pin_lowest_tenth_in_x(mesh);
  const StepInput input = liver_input(pins);
  for (SoftBody* body : {&approximate, &converged}) {
    for (int step = 0; step < steps; ++step) {
      body->step(1.0 / 60.0, input);
    }
  }
  const Eigen::Matrix3Xd& exact = converged.positions();
  const double motion = std::sqrt((exact - mesh.rest_positions()).colwise().squaredNorm().mean());
  return std::sqrt((approximate.positions() - exact).colwise().squaredNorm().mean()) / motion;
}

}  // namespace softbench::bench
