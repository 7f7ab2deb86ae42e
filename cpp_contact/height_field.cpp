#include "height_field.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rf {

HeightField::HeightField(const std::vector<V2<double>>& vertices, double period) : period_(period) {
  const std::size_t n = vertices.size();
  if (!(period > 0.0) || !std::isfinite(period))
    throw std::invalid_argument("node-to-surface contact needs a periodic rigid master (period > 0)");
  if (n < 4) throw std::invalid_argument("node-to-surface contact: a height field needs at least 4 vertices");
  x0_ = vertices[0].x;
  dx_ = period / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double expected = x0_ + static_cast<double>(i) * dx_;
    if (std::abs(vertices[i].x - expected) > 1e-6 * dx_ || !std::isfinite(vertices[i].y)) {
      std::ostringstream m;
      m << "node-to-surface contact: the rigid master must be sampled at uniform x over its period (vertex " << i
        << " at x = " << vertices[i].x << ", expected " << expected << "); use mortar or node-to-segment contact";
      throw std::invalid_argument(m.str());
    }
  }
  z_.resize(n);
  for (std::size_t i = 0; i < n; ++i) z_[i] = vertices[i].y;
  // periodic spline: M_{i-1} + 4 M_i + M_{i+1} = 6 (z_{i+1} - 2 z_i + z_{i-1}) / dx^2. The cyclic
  // matrix is strictly diagonally dominant (Jacobi spectral radius 1/2): Gauss-Seidel converges
  // by at least a factor 2 per sweep, so 80 sweeps reach round-off.
  std::vector<double> rhs(n);
  double scale = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double zp = z_[(i + n - 1) % n], zn = z_[(i + 1) % n];
    rhs[i] = 6.0 * (zn - 2.0 * z_[i] + zp) / (dx_ * dx_);
    scale = std::max(scale, std::abs(rhs[i]));
  }
  m_.assign(n, 0.0);
  for (int sweep = 0; sweep < 200; ++sweep) {
    double change = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double next = (rhs[i] - m_[(i + n - 1) % n] - m_[(i + 1) % n]) / 4.0;
      change = std::max(change, std::abs(next - m_[i]));
      m_[i] = next;
    }
    if (change <= 1e-15 * scale) break;
  }
}

HeightValue HeightField::operator()(double x) const {
  const std::size_t n = z_.size();
  double s = std::fmod((x - x0_) / dx_, static_cast<double>(n));
  if (s < 0.0) s += static_cast<double>(n);
  std::size_t i = static_cast<std::size_t>(s);
  if (i >= n) i = n - 1;  // s rounded up to n
  const double t = s - static_cast<double>(i), u = 1.0 - t;
  const std::size_t j = (i + 1) % n;
  const double Mi = m_[i], Mj = m_[j], h2 = dx_ * dx_;
  HeightValue v;
  v.h = u * z_[i] + t * z_[j] + h2 / 6.0 * ((u * u * u - u) * Mi + (t * t * t - t) * Mj);
  v.d1 = (z_[j] - z_[i]) / dx_ + dx_ / 6.0 * ((1.0 - 3.0 * u * u) * Mi + (3.0 * t * t - 1.0) * Mj);
  v.d2 = u * Mi + t * Mj;
  v.d3 = (Mj - Mi) / dx_;
  return v;
}

}  // namespace rf
