// SPDX-License-Identifier: MIT
#include "render/surface_frame.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"

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

void BodySurface::append(const Eigen::Matrix3Xd& positions, SurfaceFrame& frame) const {
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
  for (Eigen::Index t = 0; t < tets_.cols(); ++t) {
    if (!is_inverted(tets_, t, positions)) {
      continue;
    }
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
}

void append_instrument(const TriMesh& instrument,
                       const Eigen::Isometry3d& pose,
                       SurfaceFrame& frame) {
  for (int t = 0; t < instrument.num_triangles(); ++t) {
    const Eigen::Vector3d a = pose * instrument.vertices.col(instrument.triangles(0, t));
    const Eigen::Vector3d b = pose * instrument.vertices.col(instrument.triangles(1, t));
    const Eigen::Vector3d c = pose * instrument.vertices.col(instrument.triangles(2, t));
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double length = cross.norm();
    if (!(length > 0.0)) {
      continue;  // a degenerate triangle draws nothing
    }
    const Eigen::Vector3d normal = cross / length;
    const auto first = static_cast<std::uint32_t>(frame.num_vertices());
    for (const Eigen::Vector3d* corner : {&a, &b, &c}) {
      frame.add_vertex(*corner, normal, kInstrumentColour);
    }
    frame.indices.insert(frame.indices.end(), {first, first + 1, first + 2});
  }
}

}  // namespace softbench::render
