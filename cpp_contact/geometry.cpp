#include "geometry.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace rf {

double project_on_segment(const Vec2& p, const Vec2& a, const Vec2& b, Vec2& closest) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  if (!(len2 > 0.0)) throw std::invalid_argument("project_on_segment: zero-length segment");
  double xi = (p - a).dot(d) / len2;
  xi = std::min(1.0, std::max(0.0, xi));
  closest = a + xi * d;
  return xi;
}

Projection project_on_polyline(const Vec2& p, const std::vector<Vec2>& vertices) {
  if (vertices.size() < 2) throw std::invalid_argument("project_on_polyline: need >= 2 vertices");
  Projection best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s + 1 < vertices.size(); ++s) {
    Vec2 c;
    const double xi = project_on_segment(p, vertices[s], vertices[s + 1], c);
    const double d2 = (p - c).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best.segment = static_cast<std::ptrdiff_t>(s);
      best.xi = xi;
      best.point = c;
      const Vec2 t = vertices[s + 1] - vertices[s];
      const Vec2 n(-t.y(), t.x());
      best.distance = std::copysign(std::sqrt(d2), (p - c).dot(n));
    }
  }
  return best;
}

}  // namespace rf
