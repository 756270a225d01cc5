// SPDX-License-Identifier: MIT
#include "render/surface_frame.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"

#include <cmath>
#include <numbers>
#include <utility>

namespace softbench::render {

void SurfaceFrame::add_vertex(const Eigen::Vector3d& position,
                              const Eigen::Vector3d& normal,
                              const Eigen::Vector3f& colour) {
  const Eigen::Vector3f p = position.cast<float>();
  const Eigen::Vector3f n = normal.cast<float>();
  vertices.insert(vertices.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z(), colour.x(),
                                   colour.y(), colour.z()});
}

BodySurface::BodySurface(const TetMesh& mesh)
    : tets_(mesh.tets()), surface_(boundary_surface(mesh, &surface_vertices_)) {
  surface_index_.assign(static_cast<std::size_t>(mesh.num_vertices()), -1);
  for (std::size_t i = 0; i < surface_vertices_.size(); ++i) {
    surface_index_[static_cast<std::size_t>(surface_vertices_[i])] = static_cast<int>(i);
  }
}

int BodySurface::append(const Eigen::Matrix3Xd& positions, SurfaceFrame& frame) const {
  const auto count = static_cast<Eigen::Index>(surface_vertices_.size());
  Eigen::Matrix3Xd normals = Eigen::Matrix3Xd::Zero(3, count);
  for (Eigen::Index t = 0; t < surface_.triangles.cols(); ++t) {
    const Eigen::Vector3d a = positions.col(surface_vertices_[surface_.triangles(0, t)]);
    const Eigen::Vector3d b = positions.col(surface_vertices_[surface_.triangles(1, t)]);
    const Eigen::Vector3d c = positions.col(surface_vertices_[surface_.triangles(2, t)]);
    const Eigen::Vector3d area_normal = (b - a).cross(c - a);  // twice the area, outward
    for (int k = 0; k < 3; ++k) {
      normals.col(surface_.triangles(k, t)) += area_normal;
    }
  }
  std::vector<std::uint8_t> marked(static_cast<std::size_t>(count), 0);
  int inverted = 0;
  for (Eigen::Index t = 0; t < tets_.cols(); ++t) {
    if (!is_inverted(tets_, t, positions)) {
      continue;
    }
    ++inverted;
    for (int k = 0; k < 4; ++k) {
      const int index = surface_index_[static_cast<std::size_t>(tets_(k, t))];
      if (index >= 0) {
        marked[static_cast<std::size_t>(index)] = 1;
      }
    }
  }
  const auto first = static_cast<std::uint32_t>(frame.num_vertices());
  for (Eigen::Index v = 0; v < count; ++v) {
    const double length = normals.col(v).norm();
    const Eigen::Vector3d normal =
        length > 0.0 ? Eigen::Vector3d(normals.col(v) / length) : Eigen::Vector3d::UnitZ();
    frame.add_vertex(positions.col(surface_vertices_[static_cast<std::size_t>(v)]), normal,
                     marked[static_cast<std::size_t>(v)] != 0 ? kInvertedColour
                                                                : kTissueColour);
  }
  for (Eigen::Index t = 0; t < surface_.triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      frame.indices.push_back(first + static_cast<std::uint32_t>(surface_.triangles(k, t)));
    }
  }
  return inverted;
}

std::optional<SurfaceHit> BodySurface::pick(const Eigen::Matrix3Xd& positions,
                                            const Ray& ray) const {
  std::optional<SurfaceHit> nearest;
  for (Eigen::Index t = 0; t < surface_.triangles.cols(); ++t) {
    std::array<int, 3> corners{};
    for (int k = 0; k < 3; ++k) {
      corners[static_cast<std::size_t>(k)] =
          surface_vertices_[static_cast<std::size_t>(surface_.triangles(k, t))];
    }
    const Eigen::Vector3d a = positions.col(corners[0]);
    const Eigen::Vector3d ab = positions.col(corners[1]) - a;
    const Eigen::Vector3d ac = positions.col(corners[2]) - a;
    // Moeller-Trumbore: the ray's distance and the hit's weights on b and c.
    const Eigen::Vector3d p = ray.direction.cross(ac);
    const double determinant = ab.dot(p);
    if (std::abs(determinant) < 1e-30) {
      continue;  // parallel to the triangle, or a degenerate one
    }
    const Eigen::Vector3d s = ray.origin - a;
    const double u = s.dot(p) / determinant;
    const Eigen::Vector3d q = s.cross(ab);
    const double v = ray.direction.dot(q) / determinant;
    const double distance = ac.dot(q) / determinant;
    if (u < 0.0 || v < 0.0 || u + v > 1.0 || distance <= 0.0
        || (nearest && distance >= nearest->distance)) {
      continue;
    }
    SurfaceHit hit;
    hit.distance = distance;
    hit.point = ray.origin + distance * ray.direction;
    hit.normal = ab.cross(ac).normalized();
    hit.vertices = corners;
    hit.weights = Eigen::Vector3d(1.0 - u - v, u, v);
    nearest = hit;
  }
  return nearest;
}

void append_tet_faces(const Eigen::Matrix4Xi& tets,
                      const Eigen::Matrix3Xd& positions,
                      const Eigen::Vector3f& colour,
                      SurfaceFrame& frame) {
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    const auto first = static_cast<std::uint32_t>(frame.num_vertices());
    for (int k = 0; k < 4; ++k) {
      frame.add_vertex(positions.col(tets(k, t)), Eigen::Vector3d::UnitZ(), colour);
    }
    for (const auto& face : kFaces) {
      frame.indices.insert(frame.indices.end(),
                           {first + static_cast<std::uint32_t>(face[0]),
                            first + static_cast<std::uint32_t>(face[1]),
                            first + static_cast<std::uint32_t>(face[2])});
    }
  }
}

namespace {

/// Two unit vectors that make a right-handed frame with unit `axis`.
std::pair<Eigen::Vector3d, Eigen::Vector3d> frame_around(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d other =
      std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = axis.cross(other).normalized();
  return {u, axis.cross(u)};
}

/// Appends one flat-shaded triangle.
void add_facet(const Eigen::Vector3d& a,
               const Eigen::Vector3d& b,
               const Eigen::Vector3d& c,
               const Eigen::Vector3f& colour,
               SurfaceFrame& frame) {
  const Eigen::Vector3d cross = (b - a).cross(c - a);
  const double length = cross.norm();
  if (!(length > 0.0)) {
    return;  // a degenerate triangle draws nothing
  }
  const auto first = static_cast<std::uint32_t>(frame.num_vertices());
  for (const Eigen::Vector3d* corner : {&a, &b, &c}) {
    frame.add_vertex(*corner, cross / length, colour);
  }
  frame.indices.insert(frame.indices.end(), {first, first + 1, first + 2});
}

}  // namespace

void append_arrow(const Eigen::Vector3d& from,
                  const Eigen::Vector3d& to,
                  double radius,
                  const Eigen::Vector3f& colour,
                  SurfaceFrame& frame) {
  const Eigen::Vector3d along = to - from;
  const double length = along.norm();
  if (!(length > 0.0)) {
    return;
  }
  const Eigen::Vector3d axis = along / length;
  const auto [u, w] = frame_around(axis);
  const double head = std::min(0.3 * length, 6.0 * radius);
  const Eigen::Vector3d neck = to - head * axis;
  constexpr int kSides = 10;
  for (int k = 0; k < kSides; ++k) {
    const double a0 = 2.0 * std::numbers::pi * k / kSides;
    const double a1 = 2.0 * std::numbers::pi * (k + 1) / kSides;
    const Eigen::Vector3d r0 = std::cos(a0) * u + std::sin(a0) * w;
    const Eigen::Vector3d r1 = std::cos(a1) * u + std::sin(a1) * w;
    add_facet(from + radius * r0, from + radius * r1, neck + radius * r1, colour, frame);
    add_facet(from + radius * r0, neck + radius * r1, neck + radius * r0, colour, frame);
    add_facet(neck + 2.5 * radius * r0, neck + 2.5 * radius * r1, to, colour, frame);
  }
}

void append_marker(const Eigen::Vector3d& point,
                   double size,
                   const Eigen::Vector3f& colour,
                   SurfaceFrame& frame) {
  const Eigen::Vector3d axes[3] = {size * Eigen::Vector3d::UnitX(),
                                   size * Eigen::Vector3d::UnitY(),
                                   size * Eigen::Vector3d::UnitZ()};
  for (int sx : {-1, 1}) {
    for (int sy : {-1, 1}) {
      for (int sz : {-1, 1}) {
        const Eigen::Vector3d a = point + sx * axes[0];
        const Eigen::Vector3d b = point + sy * axes[1];
        const Eigen::Vector3d c = point + sz * axes[2];
        // Counter-clockwise seen from outside whatever the octant's signs.
        if (sx * sy * sz > 0) {
          add_facet(a, b, c, colour, frame);
        } else {
          add_facet(a, c, b, colour, frame);
        }
      }
    }
  }
}

void append_instrument(const TriMesh& instrument,
                       const Eigen::Isometry3d& pose,
                       SurfaceFrame& frame) {
  for (int t = 0; t < instrument.num_triangles(); ++t) {
    add_facet(pose * instrument.vertices.col(instrument.triangles(0, t)),
              pose * instrument.vertices.col(instrument.triangles(1, t)),
              pose * instrument.vertices.col(instrument.triangles(2, t)), kInstrumentColour,
              frame);
  }
}

}  // namespace softbench::render
