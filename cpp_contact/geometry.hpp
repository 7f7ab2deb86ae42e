// Geometry of 2D polylines: closest-point projection onto segments, optionally periodic.
// Plane x-z (stored as x, y = z). Used by the contact search and by the mortar projection.
#pragma once

#include <Eigen/Dense>

#include <cstddef>
#include <vector>

namespace rf {

using Vec2 = Eigen::Vector2d;

/// Result of projecting a point onto a polyline.
struct Projection {
  std::ptrdiff_t segment = -1;  ///< index of the closest segment (-1: none)
  double xi = 0.0;              ///< local coordinate on the segment, in [0, 1]
  double distance = 0.0;        ///< signed distance (positive on the side of the left normal)
  Vec2 point = Vec2::Zero();    ///< closest point
};

/// Closest point of `p` on segment [a, b]; returns xi in [0, 1].
double project_on_segment(const Vec2& p, const Vec2& a, const Vec2& b, Vec2& closest);

/// Closest point of `p` on an open polyline given by its vertices (n x 2, row-major).
Projection project_on_polyline(const Vec2& p, const std::vector<Vec2>& vertices);

}  // namespace rf
