// SPDX-License-Identifier: MIT
// The XPBD model: construction (all precomputation), state, energy, the constraints' energy
// density. The step is in xpbd_step.cpp, the parameters in xpbd_params.cpp.
#include "models/xpbd/xpbd.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "models/linear_tet.h"
#include "models/memory_bytes.h"
#include "models/xpbd/xpbd_model.h"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>
#include <vector>

namespace softbench {
namespace xpbd {
namespace {

/// The order the sweep visits the tets: mesh order, except that each tet is the first of the
/// next kLookAhead in mesh order that shares no vertex with the kWindow tets visited before it
/// (if none does, simply the next). Why: in mesh order neighbours follow each other, and a tet
/// that reads the positions the previous one just wrote waits for its whole chain of ~250
/// dependent operations; tets that share no vertex overlap in the processor. The order stays
/// local (the positions stay in cache) and fixed, so runs stay bit-identical.
std::vector<int> sweep_order(const Eigen::Matrix4Xi& tets, int num_vertices) {
  constexpr int kWindow = 2;
  constexpr std::size_t kLookAhead = 64;
  const auto count = static_cast<std::size_t>(tets.cols());
  std::vector<int> remaining(count);
  for (std::size_t t = 0; t < count; ++t) {
    remaining[t] = static_cast<int>(t);
  }
  // The position in the order at which each vertex was last touched (-kWindow - 1: never).
  std::vector<int> last_touched(static_cast<std::size_t>(num_vertices), -kWindow - 1);
  std::vector<int> order;
  order.reserve(count);
  std::size_t first = 0;  // remaining[first..] are the tets not yet ordered, in mesh order
  while (first < count) {
    const int position = static_cast<int>(order.size());
    std::size_t pick = first;
    for (std::size_t k = first; k < std::min(count, first + kLookAhead); ++k) {
      bool independent = true;
      for (int a = 0; a < 4; ++a) {
        const auto v = static_cast<std::size_t>(tets(a, remaining[k]));
        independent = independent && last_touched[v] < position - kWindow;
      }
      if (independent) {
        pick = k;
        break;
      }
    }
    // Take it out, keeping the others in mesh order.
    const int tet = remaining[pick];
    for (std::size_t k = pick; k > first; --k) {
      remaining[k] = remaining[k - 1];
    }
    ++first;
    for (int a = 0; a < 4; ++a) {
      last_touched[static_cast<std::size_t>(tets(a, tet))] = position;
    }
    order.push_back(tet);
  }
  return order;
}

}  // namespace

XpbdModel::XpbdModel(const TetMesh& mesh, const Material& material, const XpbdParams& params)
    : params_(params),
      law_(neo_hookean::stable_neo_hookean(lame_parameters(material))),
      num_vertices_(mesh.num_vertices()),
      masses_(lumped_masses(mesh, material.density)),
      rest_positions_(mesh.rest_positions()),
      constraints_(mesh.num_vertices()) {
  // Every vertex of a TetMesh is in a tet of positive volume: every mass is > 0.
  inverse_masses_ = masses_.cwiseInverse();
  const Eigen::Matrix4Xi& tets = mesh.tets();
  const auto num_tets = static_cast<std::size_t>(mesh.num_tets());
  const std::vector<int> order = sweep_order(tets, num_vertices_);
  tets_.resize(num_tets);
  rest_inverses_.resize(num_tets);
  for (std::size_t t = 0; t < num_tets; ++t) {
    const int column = order[t];
    const TetRest rest = tet_rest(tet_positions(rest_positions_, tets, column));
    const Eigen::Matrix3d metric = rest.rest_inverse * rest.rest_inverse.transpose();
    const double entries[6] = {metric(0, 0), metric(1, 1), metric(2, 2),
                               metric(0, 1), metric(0, 2), metric(1, 2)};
    std::copy(std::begin(entries), std::end(entries), tets_[t].metric);
    tets_[t].det_rest_inverse = rest.rest_inverse.determinant();
    tets_[t].inverse_volume = 1.0 / rest.volume;
    rest_inverses_[t] = rest.rest_inverse;
    for (int a = 0; a < 4; ++a) {
      tets_[t].vertices[a] = tets(a, column);
    }
  }
  // Per vertex the tets around it (in sweep order): what bind() marks as holding a vertex.
  Eigen::Matrix4Xi sweep_tets(4, static_cast<Eigen::Index>(num_tets));
  for (std::size_t t = 0; t < num_tets; ++t) {
    for (int a = 0; a < 4; ++a) {
      sweep_tets(a, static_cast<Eigen::Index>(t)) = tets_[t].vertices[a];
    }
  }
  Incidences incidences = vertex_corners(sweep_tets, num_vertices_);
  vertex_offsets_ = std::move(incidences.offsets);
  vertex_tets_ = std::move(incidences.items);
  for (int& corner : vertex_tets_) {
    corner /= 4;
  }

  // The fastest rate at which the constraints' explicit part can grow (stability_rate_).
  double stiffest = 0.0;
  for (std::size_t t = 0; t < num_tets; ++t) {
    const double volume = 1.0 / tets_[t].inverse_volume;
    const Matrix34d gradients = shape_gradients(TetRest{rest_inverses_[t], volume});
    double sum = 0.0;
    for (int a = 0; a < 4; ++a) {
      sum += inverse_masses_[tets_[t].vertices[a]] * gradients.col(a).squaredNorm();
    }
    stiffest = std::max(stiffest, sum * volume);
  }
  stability_rate_ = std::sqrt(law_.mu * stiffest);

  paired_.assign(num_tets, 0);
  for (std::size_t t = 0; t + 1 < num_tets; ++t) {
    bool shared = false;
    for (const int a : tets_[t].vertices) {
      for (const int b : tets_[t + 1].vertices) {
        shared = shared || a == b;
      }
    }
    paired_[t] = shared ? 0 : 1;
  }

  const auto vertices = static_cast<std::size_t>(num_vertices_);
  multipliers_.assign(num_tets, Eigen::Vector2d::Zero());
  holds_.assign(vertices, Hold::kFree);
  general_.assign(num_tets, 0);
  mobility_.assign(vertices, Eigen::Matrix3d::Zero());
  starts_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  predictions_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  impulses_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  attachment_lambdas_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  previous_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  reset();
}

nlohmann::json XpbdModel::parameters() const {
  return param_table().to_json(params_);
}

void XpbdModel::reset() {
  positions_ = rest_positions_;
  velocities_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  constraint_forces_ = Eigen::Matrix3Xd::Zero(3, num_vertices_);
  std::fill(multipliers_.begin(), multipliers_.end(), Eigen::Vector2d::Zero());
}

void XpbdModel::set_velocities(const Eigen::Matrix3Xd& velocities) {
  check_velocities(velocities);
  velocities_ = velocities;
}

void XpbdModel::set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) {
  check_state(positions, velocities);
  positions_ = positions;
  velocities_ = velocities;
}

int XpbdModel::substeps_for(double dt) const {
  if (!(params_.stability_ratio > 0.0)) {
    return params_.substeps;
  }
  const double needed = std::ceil(dt * stability_rate_ / std::sqrt(params_.stability_ratio));
  if (!(needed > params_.substeps)) {
    return params_.substeps;  // also for a NaN dt, which the step then reports as not finite
  }
  return needed < kMaxSubsteps ? static_cast<int>(needed) : kMaxSubsteps;
}

Eigen::Matrix3d XpbdModel::deformation(std::size_t t) const {
  const Tet& tet = tets_[t];
  Eigen::Matrix3d edges;
  for (int k = 0; k < 3; ++k) {
    edges.col(k) = positions_.col(tet.vertices[k + 1]) - positions_.col(tet.vertices[0]);
  }
  return edges * rest_inverses_[t];
}

double XpbdModel::elastic_energy() const {
  double energy = 0.0;
  for (std::size_t t = 0; t < tets_.size(); ++t) {
    energy += neo_hookean::energy_density(deformation(t), law_) / tets_[t].inverse_volume;
  }
  return energy;
}

std::size_t XpbdModel::memory_bytes() const {
  return bytes_of_elements(tets_) + bytes_of_elements(rest_inverses_) + bytes_of(masses_)
         + bytes_of(inverse_masses_) + bytes_of(rest_positions_)
         + bytes_of_elements(vertex_offsets_) + bytes_of_elements(vertex_tets_)
         + bytes_of_elements(paired_) + bytes_of(positions_) + bytes_of(velocities_)
         + bytes_of(constraint_forces_) + bytes_of_elements(multipliers_)
         + constraints_.memory_bytes() + bytes_of_elements(holds_) + bytes_of_elements(general_)
         + bytes_of_elements(mobility_) + bytes_of(starts_) + bytes_of(predictions_)
         + bytes_of(impulses_) + bytes_of(attachment_lambdas_) + bytes_of(previous_);
}

}  // namespace xpbd

std::unique_ptr<SoftBody> make_xpbd(const TetMesh& mesh,
                                    const Material& material,
                                    const XpbdParams& params) {
  validate_material(material, "make_xpbd: material");
  xpbd::validate(params, "make_xpbd: XpbdParams");
  return std::make_unique<xpbd::XpbdModel>(mesh, material, params);
}

}  // namespace softbench
