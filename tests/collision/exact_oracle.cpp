// SPDX-License-Identifier: MIT
#include "tests/collision/exact_oracle.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <variant>

namespace softbench::collision::test {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;
/// A triangle as the set it is: proper, a segment or a point.
using Shape = std::variant<Triangle, Segment, Point>;

Point point(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

Shape reduce(const Point& a, const Point& b, const Point& c) {
  if (!CGAL::collinear(a, b, c)) {
    return Triangle(a, b, c);
  }
  if (a == b && b == c) {
    return a;
  }
  // The hull of three collinear points: the pair with the third between them.
  if (CGAL::collinear_are_ordered_along_line(a, b, c)) {
    return Segment(a, c);
  }
  if (CGAL::collinear_are_ordered_along_line(b, a, c)) {
    return Segment(b, c);
  }
  return Segment(a, b);
}

bool meets(const Shape& s, const Shape& t) {
  return std::visit(
      [](const auto& x, const auto& y) -> bool {
        using X = std::decay_t<decltype(x)>;
        using Y = std::decay_t<decltype(y)>;
        if constexpr (std::is_same_v<X, Point> && std::is_same_v<Y, Point>) {
          return x == y;
        } else if constexpr (std::is_same_v<X, Point> && std::is_same_v<Y, Segment>) {
          return y.has_on(x);
        } else if constexpr (std::is_same_v<X, Segment> && std::is_same_v<Y, Point>) {
          return x.has_on(y);
        } else if constexpr (std::is_same_v<X, Point> && std::is_same_v<Y, Triangle>) {
          return y.has_on(x);
        } else if constexpr (std::is_same_v<X, Triangle> && std::is_same_v<Y, Point>) {
          return x.has_on(y);
        } else {
          return CGAL::do_intersect(x, y);
        }
      },
      s, t);
}

bool in_plane(const Triangle& t, const Shape& s) {
  auto on = [&](const Point& p) {
    return CGAL::orientation(t[0], t[1], t[2], p) == CGAL::COPLANAR;
  };
  return std::visit(
      [&](const auto& x) -> bool {
        using X = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<X, Point>) {
          return false;  // a point contact is a kSegment of length zero
        } else if constexpr (std::is_same_v<X, Segment>) {
          return on(x[0]) && on(x[1]);
        } else {
          return on(x[0]) && on(x[1]) && on(x[2]);
        }
      },
      s);
}

}  // namespace

TriTriContact exact_contact(const Eigen::Vector3d& p0,
                            const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& p2,
                            const Eigen::Vector3d& q0,
                            const Eigen::Vector3d& q1,
                            const Eigen::Vector3d& q2) {
  const Shape a = reduce(point(p0), point(p1), point(p2));
  const Shape b = reduce(point(q0), point(q1), point(q2));
  if (!meets(a, b)) {
    return TriTriContact::kDisjoint;
  }
  const auto* ta = std::get_if<Triangle>(&a);
  const auto* tb = std::get_if<Triangle>(&b);
  if (ta != nullptr && in_plane(*ta, b)) {
    return TriTriContact::kCoplanar;
  }
  if (tb != nullptr && in_plane(*tb, a)) {
    return TriTriContact::kCoplanar;
  }
  return TriTriContact::kSegment;
}

bool exact_intersect(const Eigen::Vector3d& p0,
                     const Eigen::Vector3d& p1,
                     const Eigen::Vector3d& p2,
                     const Eigen::Vector3d& q0,
                     const Eigen::Vector3d& q1,
                     const Eigen::Vector3d& q2) {
  return meets(reduce(point(p0), point(p1), point(p2)), reduce(point(q0), point(q1), point(q2)));
}

bool exactly_degenerate(const Eigen::Vector3d& p0,
                        const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& p2) {
  return CGAL::collinear(point(p0), point(p1), point(p2));
}

double squared_distance_to_triangle(const Eigen::Vector3d& x,
                                    const Eigen::Vector3d& p0,
                                    const Eigen::Vector3d& p1,
                                    const Eigen::Vector3d& p2) {
  return CGAL::squared_distance(point(x), Triangle(point(p0), point(p1), point(p2)));
}

}  // namespace softbench::collision::test
