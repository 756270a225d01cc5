// SPDX-License-Identifier: MIT
#include "collision/closest_point_triangle.h"

namespace softbench::collision {
namespace {

using F = TriangleFeature;

const Eigen::Vector3d kCorner[3] = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0),
                                    Eigen::Vector3d(0, 0, 1)};

// Closest point of segment [a, b] (triangle vertices i and j) to p; `inside` names the edge.
TrianglePoint closest_on_segment(const Eigen::Vector3d& p,
                                 const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b,
                                 int i,
                                 int j,
                                 TriangleFeature inside) {
  const Eigen::Vector3d ab = b - a;
  const double length_squared = ab.squaredNorm();
  const double t = (p - a).dot(ab);
  if (t <= 0.0 || length_squared == 0.0) {
    return {a, kCorner[i], static_cast<F>(static_cast<int>(F::kVertex0) + i)};
  }
  if (t >= length_squared) {
    return {b, kCorner[j], static_cast<F>(static_cast<int>(F::kVertex0) + j)};
  }
  const double s = t / length_squared;
  return {a + ab * s, (1.0 - s) * kCorner[i] + s * kCorner[j], inside};
}

TrianglePoint closest_on_edges(const Eigen::Vector3d& p,
                               const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c) {
  const TrianglePoint candidates[3] = {closest_on_segment(p, a, b, 0, 1, F::kEdge01),
                                       closest_on_segment(p, b, c, 1, 2, F::kEdge12),
                                       closest_on_segment(p, c, a, 2, 0, F::kEdge20)};
  const TrianglePoint* best = &candidates[0];
  for (const TrianglePoint& candidate : candidates) {
    if ((candidate.point - p).squaredNorm() < (best->point - p).squaredNorm()) {
      best = &candidate;
    }
  }
  return *best;
}

}  // namespace

TrianglePoint closest_point_on_triangle(const Eigen::Vector3d& p,
                                        const Eigen::Vector3d& a,
                                        const Eigen::Vector3d& b,
                                        const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    return {a, kCorner[0], F::kVertex0};
  }
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    return {b, kCorner[1], F::kVertex1};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    return {c, kCorner[2], F::kVertex2};
  }
  // Barycentric-area terms; their sum is |ab x ac|^2 >= 0, zero for a degenerate triangle.
  const double vc = d1 * d4 - d3 * d2;
  const double vb = d5 * d2 - d1 * d6;
  const double va = d3 * d6 - d5 * d4;
  const double area_term = va + vb + vc;
  if (!(area_term > 0.0)) {
    return closest_on_edges(p, a, b, c);
  }
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + ab * v, Eigen::Vector3d(1.0 - v, v, 0.0), F::kEdge01};
  }
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + ac * w, Eigen::Vector3d(1.0 - w, 0.0, w), F::kEdge20};
  }
  const double e = d4 - d3, f = d5 - d6;
  if (va <= 0.0 && e >= 0.0 && f >= 0.0 && e + f > 0.0) {
    const double w = e / (e + f);
    return {b + (c - b) * w, Eigen::Vector3d(0.0, 1.0 - w, w), F::kEdge12};
  }
  const double v = vb / area_term, w = vc / area_term;
  return {a + ab * v + ac * w, Eigen::Vector3d(1.0 - v - w, v, w), F::kFace};
}

}  // namespace softbench::collision
