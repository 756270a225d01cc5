// SPDX-License-Identifier: MIT
#include "geometry/surface_smoothing.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <utility>
#include <vector>

// Taubin 1995, "A signal processing approach to fair surface design". With the uniform umbrella
// operator L(x_i) = mean of the neighbours - x_i, one step x <- x + f L(x) scales each frequency
// k of the mesh signal by (1 - f k). A shrinking step (f = lambda > 0) followed by an inflating
// one (f = mu < -lambda) gives the transfer function (1 - lambda k)(1 - mu k), which is about 1
// below the pass-band frequency 1/lambda + 1/mu and damps higher ones: noise goes, the shape (and
// its volume) stays, unlike plain Laplacian smoothing, whose (1 - lambda k)^n shrinks everything.
namespace softbench {
namespace {

/// Each vertex's neighbours (the other ends of its edges) in compressed rows.
struct VertexNeighbours {
  std::vector<int> offsets;  // #V + 1
  std::vector<int> indices;
};

VertexNeighbours vertex_neighbours(const Eigen::Matrix3Xi& triangles, int num_vertices) {
  // Every triangle edge in both directions; an edge of two triangles appears twice, so sort and
  // drop duplicates to weigh each neighbour once.
  std::vector<std::pair<int, int>> directed;
  directed.reserve(static_cast<std::size_t>(triangles.cols()) * 6);
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = triangles(corner, t);
      const int b = triangles((corner + 1) % 3, t);
      if (a < 0 || a >= num_vertices || b < 0 || b >= num_vertices) {
        throw std::invalid_argument(
            "taubin_smooth: a triangle indexes a vertex that does not exist");
      }
      directed.emplace_back(a, b);
      directed.emplace_back(b, a);
    }
  }
  std::sort(directed.begin(), directed.end());
  directed.erase(std::unique(directed.begin(), directed.end()), directed.end());

  VertexNeighbours neighbours;
  neighbours.offsets.assign(static_cast<std::size_t>(num_vertices) + 1, 0);
  neighbours.indices.reserve(directed.size());
  for (const auto& [from, to] : directed) {
    ++neighbours.offsets[static_cast<std::size_t>(from) + 1];
    neighbours.indices.push_back(to);
  }
  for (std::size_t v = 0; v < static_cast<std::size_t>(num_vertices); ++v) {
    neighbours.offsets[v + 1] += neighbours.offsets[v];
  }
  return neighbours;
}

/// One umbrella step x <- x + factor * L(x), all vertices updated from the old positions.
void umbrella_step(const VertexNeighbours& neighbours,
                   double factor,
                   Eigen::Matrix3Xd& positions,
                   Eigen::Matrix3Xd& scratch) {
  scratch = positions;
  for (Eigen::Index v = 0; v < positions.cols(); ++v) {
    const int begin = neighbours.offsets[static_cast<std::size_t>(v)];
    const int end = neighbours.offsets[static_cast<std::size_t>(v) + 1];
    if (begin == end) {
      continue;  // an isolated vertex has no umbrella and stays put
    }
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int n = begin; n < end; ++n) {
      sum += scratch.col(neighbours.indices[static_cast<std::size_t>(n)]);
    }
    const Eigen::Vector3d umbrella = sum / static_cast<double>(end - begin) - scratch.col(v);
    positions.col(v) += factor * umbrella;
  }
}

}  // namespace

void taubin_smooth(TriMesh& surface, int iterations, double lambda, double mu) {
  if (iterations <= 0) {
    return;
  }
  const VertexNeighbours neighbours = vertex_neighbours(surface.triangles, surface.num_vertices());
  Eigen::Matrix3Xd scratch;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    umbrella_step(neighbours, lambda, surface.vertices, scratch);
    umbrella_step(neighbours, mu, surface.vertices, scratch);
  }
}

}  // namespace softbench
