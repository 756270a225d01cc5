// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "render/camera.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace softbench::render {

/// What one picture draws: triangles with a position, a normal and a colour per vertex
/// (interleaved, 9 floats a vertex: what SurfaceRenderer uploads as it is).
struct SurfaceFrame {
  static constexpr int kFloatsPerVertex = 9;
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices;

  int num_vertices() const { return static_cast<int>(vertices.size()) / kFloatsPerVertex; }
  void clear() {  ///< empty, keeping the storage for the next frame
    vertices.clear();
    indices.clear();
  }
  void add_vertex(const Eigen::Vector3d& position,
                  const Eigen::Vector3d& normal,
                  const Eigen::Vector3f& colour);
};

/// Tissue, a tet's corner where the tet is inverted, and the instrument (linear RGB).
inline const Eigen::Vector3f kTissueColour(0.78F, 0.36F, 0.32F);
inline const Eigen::Vector3f kInvertedColour(1.0F, 0.85F, 0.10F);
inline const Eigen::Vector3f kInstrumentColour(0.62F, 0.66F, 0.72F);
/// Contact points and the tool's force (what the tissue does to the tool).
inline const Eigen::Vector3f kContactColour(0.10F, 0.45F, 0.95F);
inline const Eigen::Vector3f kForceColour(0.10F, 0.70F, 0.25F);

/// Where a ray meets a body's surface.
struct SurfaceHit {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< the triangle's, outward, unit
  double distance = 0.0;                               ///< along the ray
  std::array<int, 3> vertices{};  ///< the triangle's corners, tet-mesh vertex indices
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();  ///< the point's barycentric weights
};

/// A tet mesh's boundary surface, drawn at any positions of its vertices.
class BodySurface {
 public:
  explicit BodySurface(const TetMesh& mesh);

  /// Appends the surface at `positions` (3 x #V of the tet mesh): smooth normals (the
  /// area-weighted mean of the faces around a vertex, recomputed from these positions), and
  /// kInvertedColour on every surface vertex of a tet whose signed volume is not positive (so
  /// a picture shows where a model left the body inside out). Returns how many tets are
  /// inverted.
  int append(const Eigen::Matrix3Xd& positions, SurfaceFrame& frame) const;
  /// The nearest surface point the ray meets at `positions` (either face of a triangle), or
  /// none: what a click on the body picks.
  std::optional<SurfaceHit> pick(const Eigen::Matrix3Xd& positions, const Ray& ray) const;

 private:
  Eigen::Matrix4Xi tets_;
  std::vector<int> surface_vertices_;  ///< tet-mesh index of each surface vertex
  TriMesh surface_;                    ///< its triangles, outward, over surface_vertices_
  std::vector<int> surface_index_;     ///< per tet-mesh vertex: its surface index, or -1
};

/// Appends a rigid instrument at `pose` (mesh frame -> world), faceted: one normal per
/// triangle, as a machined tool looks.
void append_instrument(const TriMesh& instrument,
                       const Eigen::Isometry3d& pose,
                       SurfaceFrame& frame);

/// Appends every face of every tet at `positions` (shared faces twice): drawn as a wireframe,
/// the tet mesh inside the surface.
void append_tet_faces(const Eigen::Matrix4Xi& tets,
                      const Eigen::Matrix3Xd& positions,
                      const Eigen::Vector3f& colour,
                      SurfaceFrame& frame);

/// Appends an arrow from `from` to `to` (a shaft of `radius` and a head), faceted.
void append_arrow(const Eigen::Vector3d& from,
                  const Eigen::Vector3d& to,
                  double radius,
                  const Eigen::Vector3f& colour,
                  SurfaceFrame& frame);

/// Appends a small octahedron of half-width `size` at `point`: a marker.
void append_marker(const Eigen::Vector3d& point,
                   double size,
                   const Eigen::Vector3f& colour,
                   SurfaceFrame& frame);

}  // namespace softbench::render
