// SPDX-License-Identifier: MIT
#include "geometry/mesh_measures.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace softbench {
namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

// Face i of tet (x0..x3) is opposite vertex i; its normal (not normalized) points away from x_i
// for a positive tet and towards it for a negative one, the same way for all four faces.
constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

struct SingleTetQuality {
  double radius_ratio = 0.0;
  double min_dihedral_deg = std::numeric_limits<double>::infinity();
  double max_dihedral_deg = -std::numeric_limits<double>::infinity();
};

SingleTetQuality single_tet_quality(const std::array<Eigen::Vector3d, 4>& x) {
  SingleTetQuality quality;

  std::array<Eigen::Vector3d, 4> area_normals;  // |n| = twice the face area
  double total_area = 0.0;
  for (int f = 0; f < 4; ++f) {
    const auto& face = kFaces[f];
    area_normals[f] = (x[face[1]] - x[face[0]]).cross(x[face[2]] - x[face[0]]);
    total_area += 0.5 * area_normals[f].norm();
  }

  // 3 r_in / r_circ with r_in = 3 |V| / A and r_circ = |a^2 (b x c) + b^2 (c x a) + c^2 (a x b)|
  // / (12 |V|), edges a, b, c from x0: 108 V^2 / (A |...|), which goes smoothly to 0 as the tet
  // flattens instead of dividing by its vanishing volume.
  const Eigen::Vector3d a = x[1] - x[0];
  const Eigen::Vector3d b = x[2] - x[0];
  const Eigen::Vector3d c = x[3] - x[0];
  const double volume = a.dot(b.cross(c)) / 6.0;
  const double circum_numerator =
      (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) + c.squaredNorm() * a.cross(b))
          .norm();
  const double denominator = total_area * circum_numerator;
  quality.radius_ratio = denominator > 0.0 ? 108.0 * volume * volume / denominator : 0.0;

  // The interior dihedral angle at the edge shared by faces i and j is pi minus the angle between
  // their outward normals. A face of zero area has no normal, so its angles are left out.
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      const double norms = area_normals[i].norm() * area_normals[j].norm();
      if (norms == 0.0) {
        continue;
      }
      const double cosine = std::clamp(area_normals[i].dot(area_normals[j]) / norms, -1.0, 1.0);
      const double dihedral = 180.0 - std::acos(cosine) * kDegreesPerRadian;
      quality.min_dihedral_deg = std::min(quality.min_dihedral_deg, dihedral);
      quality.max_dihedral_deg = std::max(quality.max_dihedral_deg, dihedral);
    }
  }
  return quality;
}

double median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  if (values.size() % 2 == 1) {
    return *middle;
  }
  // Even count: the mean of the two middle values; the lower one is the largest below `middle`.
  return 0.5 * (*middle + *std::max_element(values.begin(), middle));
}

void require_tets_in_range(const Eigen::Matrix4Xi& tets, Eigen::Index num_vertices) {
  const bool in_range =
      tets.size() == 0 || (tets.minCoeff() >= 0 && tets.maxCoeff() < num_vertices);
  if (!in_range) {
    throw std::out_of_range("tet vertex index out of range (" + std::to_string(num_vertices)
                            + " vertices)");
  }
}

}  // namespace

double signed_tet_volume(const Eigen::Vector3d& x0,
                         const Eigen::Vector3d& x1,
                         const Eigen::Vector3d& x2,
                         const Eigen::Vector3d& x3) {
  return (x1 - x0).dot((x2 - x0).cross(x3 - x0)) / 6.0;
}

bool is_inverted(const Eigen::Matrix4Xi& tets, Eigen::Index t, const Eigen::Matrix3Xd& positions) {
  return signed_tet_volume(positions.col(tets(0, t)), positions.col(tets(1, t)),
                           positions.col(tets(2, t)), positions.col(tets(3, t)))
         <= 0.0;
}

int count_inverted_tets(const TetMesh& mesh, const Eigen::Matrix3Xd& positions) {
  int inverted = 0;
  for (Eigen::Index t = 0; t < mesh.tets().cols(); ++t) {
    inverted += is_inverted(mesh.tets(), t, positions) ? 1 : 0;
  }
  return inverted;
}

double mesh_volume(const TetMesh& mesh) {
  return mesh_volume(mesh, mesh.rest_positions());
}

double mesh_volume(const TetMesh& mesh, const Eigen::Matrix3Xd& positions) {
  if (positions.cols() != mesh.num_vertices()) {
    throw std::invalid_argument("mesh_volume: " + std::to_string(positions.cols())
                                + " positions for a mesh of " + std::to_string(mesh.num_vertices())
                                + " vertices");
  }
  const Eigen::Matrix4Xi& tets = mesh.tets();
  double volume = 0.0;
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    volume += signed_tet_volume(positions.col(tets(0, t)), positions.col(tets(1, t)),
                                positions.col(tets(2, t)), positions.col(tets(3, t)));
  }
  return volume;
}

double enclosed_volume(const TriMesh& surface) {
  if (surface.num_vertices() == 0) {
    return 0.0;
  }
  // Divergence theorem: the sum of the signed volumes of the tets joining each triangle to a fixed
  // point. The box centre as that point keeps the products small and the result independent of
  // where the surface sits in space.
  const Eigen::Vector3d centre =
      0.5 * (surface.vertices.rowwise().minCoeff() + surface.vertices.rowwise().maxCoeff());
  double volume = 0.0;
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t) {
    const auto tri = surface.triangles.col(t);
    volume += signed_tet_volume(centre, surface.vertices.col(tri(0)), surface.vertices.col(tri(1)),
                                surface.vertices.col(tri(2)));
  }
  return volume;
}

double surface_area(const TriMesh& surface) {
  double area = 0.0;
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t) {
    const auto tri = surface.triangles.col(t);
    const Eigen::Vector3d x0 = surface.vertices.col(tri(0));
    area +=
        0.5 * (surface.vertices.col(tri(1)) - x0).cross(surface.vertices.col(tri(2)) - x0).norm();
  }
  return area;
}

Eigen::Matrix<double, 3, 2> bounding_box(const Eigen::Matrix3Xd& points) {
  Eigen::Matrix<double, 3, 2> box = Eigen::Matrix<double, 3, 2>::Zero();
  if (points.cols() > 0) {
    box.col(0) = points.rowwise().minCoeff();
    box.col(1) = points.rowwise().maxCoeff();
  }
  return box;
}

double bounding_box_diagonal(const Eigen::Matrix3Xd& points) {
  const Eigen::Matrix<double, 3, 2> box = bounding_box(points);
  return (box.col(1) - box.col(0)).norm();
}

Eigen::VectorXd lumped_masses(const TetMesh& mesh, double density) {
  const Eigen::Matrix3Xd& x = mesh.rest_positions();
  const Eigen::Matrix4Xi& tets = mesh.tets();
  Eigen::VectorXd masses = Eigen::VectorXd::Zero(mesh.num_vertices());
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    const double quarter = 0.25 * density
                           * signed_tet_volume(x.col(tets(0, t)), x.col(tets(1, t)),
                                               x.col(tets(2, t)), x.col(tets(3, t)));
    for (int k = 0; k < 4; ++k) {
      masses(tets(k, t)) += quarter;
    }
  }
  return masses;
}

TetQuality tet_quality(const Eigen::Matrix3Xd& positions, const Eigen::Matrix4Xi& tets) {
  TetQuality result;
  if (tets.cols() == 0) {
    return result;
  }
  require_tets_in_range(tets, positions.cols());

  std::vector<double> radius_ratios;
  radius_ratios.reserve(static_cast<std::size_t>(tets.cols()));
  double min_dihedral = std::numeric_limits<double>::infinity();
  double max_dihedral = -std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    const std::array<Eigen::Vector3d, 4> x{positions.col(tets(0, t)), positions.col(tets(1, t)),
                                           positions.col(tets(2, t)), positions.col(tets(3, t))};
    const SingleTetQuality quality = single_tet_quality(x);
    radius_ratios.push_back(quality.radius_ratio);
    min_dihedral = std::min(min_dihedral, quality.min_dihedral_deg);
    max_dihedral = std::max(max_dihedral, quality.max_dihedral_deg);
  }

  // Only tets made of collapsed faces have no dihedral angle at all; report 0 rather than inf.
  if (min_dihedral <= max_dihedral) {
    result.min_dihedral_deg = min_dihedral;
    result.max_dihedral_deg = max_dihedral;
  }
  result.min_radius_ratio = *std::min_element(radius_ratios.begin(), radius_ratios.end());
  double sum = 0.0;
  for (const double ratio : radius_ratios) {
    sum += ratio;
  }
  result.mean_radius_ratio = sum / static_cast<double>(radius_ratios.size());
  result.median_radius_ratio = median(std::move(radius_ratios));
  return result;
}

}  // namespace softbench
