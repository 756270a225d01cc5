// SPDX-License-Identifier: MIT
#include "geometry/weld_vertices.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace softbench {
namespace {

struct Cell {
  std::int64_t x = 0;
  std::int64_t y = 0;
  std::int64_t z = 0;
  bool operator==(const Cell&) const = default;
};

struct CellHash {
  std::size_t operator()(const Cell& cell) const {
    // Multipliers from the classic spatial-hashing primes (Teschner et al. 2003).
    const auto mix = static_cast<std::uint64_t>(cell.x) * 73856093u
                     ^ static_cast<std::uint64_t>(cell.y) * 19349663u
                     ^ static_cast<std::uint64_t>(cell.z) * 83492791u;
    return std::hash<std::uint64_t>{}(mix);
  }
};

}  // namespace

WeldedVertices weld_vertices(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                             double relative_tolerance) {
  WeldedVertices result;
  const Eigen::Index count = points.cols();
  result.index_of.resize(static_cast<std::size_t>(count));
  if (count == 0) {
    return result;
  }
  const Eigen::Vector3d lowest = points.rowwise().minCoeff();
  const double diagonal = (points.rowwise().maxCoeff() - lowest).norm();
  const double tolerance = relative_tolerance * diagonal;
  // Cells no narrower than 1e-12 of the extent keep cell coordinates far inside int64, whatever
  // the tolerance; a cell wider than the tolerance only means a few more distance checks.
  double cell_size = std::max(tolerance, 1e-12 * diagonal);
  if (!(cell_size > 0.0)) {
    cell_size = 1.0;  // all points coincide: one cell holds them
  }
  const auto cell_of = [&](const Eigen::Vector3d& point) {
    const Eigen::Vector3d scaled = (point - lowest) / cell_size;
    return Cell{static_cast<std::int64_t>(std::floor(scaled.x())),
                static_cast<std::int64_t>(std::floor(scaled.y())),
                static_cast<std::int64_t>(std::floor(scaled.z()))};
  };

  std::vector<Eigen::Vector3d> kept;
  std::vector<int> next_in_cell;                           // chains kept vertices sharing a cell
  std::unordered_map<Cell, int, CellHash> newest_in_cell;  // cell -> its latest kept vertex
  const double squared_tolerance = tolerance * tolerance;
  for (Eigen::Index i = 0; i < count; ++i) {
    const Eigen::Vector3d point = points.col(i);
    const Cell cell = cell_of(point);
    int match = -1;
    for (std::int64_t dx = -1; dx <= 1 && match < 0; ++dx) {
      for (std::int64_t dy = -1; dy <= 1 && match < 0; ++dy) {
        for (std::int64_t dz = -1; dz <= 1 && match < 0; ++dz) {
          const auto found = newest_in_cell.find(Cell{cell.x + dx, cell.y + dy, cell.z + dz});
          for (int k = found == newest_in_cell.end() ? -1 : found->second; k >= 0;
               k = next_in_cell[static_cast<std::size_t>(k)]) {
            if ((kept[static_cast<std::size_t>(k)] - point).squaredNorm() <= squared_tolerance) {
              match = k;
              break;
            }
          }
        }
      }
    }
    if (match < 0) {
      match = static_cast<int>(kept.size());
      kept.push_back(point);
      auto [slot, inserted] = newest_in_cell.try_emplace(cell, match);
      next_in_cell.push_back(inserted ? -1 : slot->second);
      slot->second = match;
    }
    result.index_of[static_cast<std::size_t>(i)] = match;
  }
  result.vertices.resize(3, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t k = 0; k < kept.size(); ++k) {
    result.vertices.col(static_cast<Eigen::Index>(k)) = kept[k];
  }
  return result;
}

}  // namespace softbench
