#include "surface.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

namespace rf {

namespace {

std::string fmt(const V2<double>& p) {
  std::ostringstream s;
  s << "(" << p.x << ", " << p.y << ")";
  return s.str();
}

double orient(const V2<double>& a, const V2<double>& b, const V2<double>& c) { return cross(b - a, c - a); }

bool on_segment(const V2<double>& a, const V2<double>& b, const V2<double>& p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

}  // namespace

bool segments_intersect(const V2<double>& p1, const V2<double>& p2, const V2<double>& q1, const V2<double>& q2) {
  const double scale = std::max({norm(p2 - p1), norm(q2 - q1), 1e-300});
  const double eps = 1e-12 * scale * scale;
  auto sgn = [eps](double v) { return v > eps ? 1 : (v < -eps ? -1 : 0); };
  const int d1 = sgn(orient(q1, q2, p1)), d2 = sgn(orient(q1, q2, p2));
  const int d3 = sgn(orient(p1, p2, q1)), d4 = sgn(orient(p1, p2, q2));
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  if (d1 == 0 && on_segment(q1, q2, p1)) return true;
  if (d2 == 0 && on_segment(q1, q2, p2)) return true;
  if (d3 == 0 && on_segment(p1, p2, q1)) return true;
  if (d4 == 0 && on_segment(p1, p2, q2)) return true;
  return false;
}

SurfaceMesh make_surface(const std::string& name, std::vector<V2<double>> X, std::vector<std::array<DofIndex, 2>> dofs,
                         std::vector<std::array<int, 2>> segments, std::vector<DofIndex> temperature_dofs,
                         const std::vector<V2<double>>& interior) {
  SurfaceMesh s;
  s.name = name;
  const int n = static_cast<int>(X.size());
  auto fail = [&](const std::string& what) { throw std::invalid_argument(name + " surface: " + what); };
  if (n < 2) fail("need at least 2 nodes, got " + std::to_string(n));
  if (dofs.size() != X.size())
    fail("dofs must have one row (dof_x, dof_z) per node: " + std::to_string(dofs.size()) + " rows for " +
         std::to_string(n) + " nodes");
  if (!temperature_dofs.empty() && temperature_dofs.size() != X.size())
    fail("temperature_dofs must be empty or have one entry per node, got " + std::to_string(temperature_dofs.size()));
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(X[static_cast<std::size_t>(i)].x) || !std::isfinite(X[static_cast<std::size_t>(i)].y))
      fail("node " + std::to_string(i) + " has a non-finite coordinate " + fmt(X[static_cast<std::size_t>(i)]));
  }
  std::unordered_set<DofIndex> seen;
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 2; ++c) {
      const DofIndex d = dofs[static_cast<std::size_t>(i)][static_cast<std::size_t>(c)];
      if (d < 0) fail("node " + std::to_string(i) + " has a negative dof index " + std::to_string(d));
      if (!seen.insert(d).second) fail("dof index " + std::to_string(d) + " is used twice");
    }
    if (!temperature_dofs.empty()) {
      const DofIndex d = temperature_dofs[static_cast<std::size_t>(i)];
      if (d < 0) fail("node " + std::to_string(i) + " has a negative temperature dof index " + std::to_string(d));
      if (!seen.insert(d).second) fail("dof index " + std::to_string(d) + " is used twice");
    }
  }
  if (segments.empty()) fail("no segments given");
  s.prev.assign(static_cast<std::size_t>(n), -1);
  s.next.assign(static_cast<std::size_t>(n), -1);
  std::vector<int> start_of(static_cast<std::size_t>(n), -1), end_of(static_cast<std::size_t>(n), -1);
  s.h_min = INFINITY;
  s.h_max = 0.0;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const int a = segments[k][0], b = segments[k][1];
    const std::string sk = "segment " + std::to_string(k) + " (" + std::to_string(a) + ", " + std::to_string(b) + ")";
    if (a < 0 || a >= n || b < 0 || b >= n) fail(sk + " refers to a node outside 0.." + std::to_string(n - 1));
    if (a == b) fail(sk + " joins a node to itself");
    const double len = norm(X[static_cast<std::size_t>(b)] - X[static_cast<std::size_t>(a)]);
    if (!(len > 0.0)) fail(sk + " has zero length at " + fmt(X[static_cast<std::size_t>(a)]));
    if (start_of[static_cast<std::size_t>(a)] >= 0)
      fail("node " + std::to_string(a) + " starts two segments (" +
           std::to_string(start_of[static_cast<std::size_t>(a)]) + " and " + std::to_string(k) +
           "): segments must form chains oriented counter-clockwise around the body "
           "(bottom face from left to right, outward normal = tangent rotated clockwise)");
    if (end_of[static_cast<std::size_t>(b)] >= 0)
      fail("node " + std::to_string(b) + " ends two segments (" + std::to_string(end_of[static_cast<std::size_t>(b)]) +
           " and " + std::to_string(k) +
           "): segments must form chains oriented counter-clockwise around the body "
           "(bottom face from left to right, outward normal = tangent rotated clockwise)");
    start_of[static_cast<std::size_t>(a)] = static_cast<int>(k);
    end_of[static_cast<std::size_t>(b)] = static_cast<int>(k);
    s.next[static_cast<std::size_t>(a)] = b;
    s.prev[static_cast<std::size_t>(b)] = a;
    s.h_min = std::min(s.h_min, len);
    s.h_max = std::max(s.h_max, len);
  }
  for (int i = 0; i < n; ++i)
    if (s.prev[static_cast<std::size_t>(i)] < 0 && s.next[static_cast<std::size_t>(i)] < 0)
      fail("node " + std::to_string(i) + " belongs to no segment");
  if (!interior.empty()) {
    if (interior.size() != segments.size())
      fail("interior points: need one per segment, got " + std::to_string(interior.size()));
    for (std::size_t k = 0; k < segments.size(); ++k) {
      const V2<double> a = X[static_cast<std::size_t>(segments[k][0])], b = X[static_cast<std::size_t>(segments[k][1])];
      const V2<double> nrm = right_normal(b - a);
      const V2<double> mid = 0.5 * (a + b);
      if (!(dot(interior[k] - mid, nrm) < 0.0))
        fail("segment " + std::to_string(k) + " from " + fmt(a) + " to " + fmt(b) +
             " is oriented clockwise: its outward normal (t_y, -t_x) points into the body. "
             "Order segments counter-clockwise around the body (the bottom face of a block from left "
             "to right, outward normal -z)");
    }
  }
  s.X = std::move(X);
  s.dofs = std::move(dofs);
  s.temperature_dofs = std::move(temperature_dofs);
  s.segments = std::move(segments);
  return s;
}

RigidPolyline::RigidPolyline(std::vector<V2<double>> vertices, double period)
    : V_(std::move(vertices)), period_(period) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("rigid master polyline: " + what); };
  if (!std::isfinite(period_) || period_ < 0.0) {
    std::ostringstream m;
    m << "period must be finite and >= 0 (0 = not periodic), got " << period_;
    fail(m.str());
  }
  if (V_.size() < 2) fail("need at least 2 vertices, got " + std::to_string(V_.size()));
  for (std::size_t i = 0; i < V_.size(); ++i)
    if (!std::isfinite(V_[i].x) || !std::isfinite(V_[i].y))
      fail("vertex " + std::to_string(i) + " is not finite: " + fmt(V_[i]));
  double xmin = INFINITY, xmax = -INFINITY;
  for (const auto& v : V_) {
    xmin = std::min(xmin, v.x);
    xmax = std::max(xmax, v.x);
  }
  if (periodic()) {
    const V2<double> closing = V_.front() + V2<double>{period_, 0.0};
    const double tol = 1e-9 * std::max(period_, xmax - xmin);
    if (norm(V_.back() - closing) <= tol) {
      V_.pop_back();
      dropped_closing_ = true;
      xmax = -INFINITY;
      for (const auto& v : V_) xmax = std::max(xmax, v.x);
    } else if (std::abs(V_.back().x - closing.x) <= tol) {
      std::ostringstream m;
      m << "period " << period_ << " does not match the sample: the last vertex " << fmt(V_.back())
        << " lies at x = x_first + L but differs from the first vertex shifted by L " << fmt(closing)
        << " (the sample is not periodic with this period)";
      fail(m.str());
    }
    if (V_.size() < 2) fail("a periodic sample needs at least 2 distinct vertices per period");
    if (!(xmax - xmin < period_)) {
      std::ostringstream m;
      m << "period " << period_ << " does not match the sample: its vertices span x in [" << xmin << ", " << xmax
        << "], which is not shorter than the period (give one period of the profile, without its repeat)";
      fail(m.str());
    }
  }
  nseg_ = periodic() ? static_cast<int>(V_.size()) : static_cast<int>(V_.size()) - 1;
  std::vector<V2<double>> a(static_cast<std::size_t>(nseg_)), b(static_cast<std::size_t>(nseg_));
  std::vector<double> len(static_cast<std::size_t>(nseg_));
  for (int s = 0; s < nseg_; ++s) {
    segment(s, 0, a[static_cast<std::size_t>(s)], b[static_cast<std::size_t>(s)]);
    len[static_cast<std::size_t>(s)] = norm(b[static_cast<std::size_t>(s)] - a[static_cast<std::size_t>(s)]);
    if (!(len[static_cast<std::size_t>(s)] > 0.0)) {
      if (periodic() && s == nseg_ - 1)
        fail("zero-length wrap-around segment: the period L = " + std::to_string(period_) +
             " equals the extent of the sample; for k samples with spacing dx the period is k*dx");
      fail("segment " + std::to_string(s) + " has zero length (vertices " + std::to_string(s) + " and " +
           std::to_string(s + 1) + " coincide at " + fmt(a[static_cast<std::size_t>(s)]) + ")");
    }
  }
  h_min_ = *std::min_element(len.begin(), len.end());
  h_max_ = *std::max_element(len.begin(), len.end());
  if (periodic() && nseg_ >= 3) {
    std::vector<double> sorted(len.begin(), len.end() - 1);
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    const double median = sorted[sorted.size() / 2];
    const double wrap = len.back();
    if (wrap > 4.0 * median) {
      std::ostringstream m;
      m << "period " << period_ << " does not match the sample: the wrap-around segment from " << fmt(V_.back())
        << " to " << fmt(V_.front() + V2<double>{period_, 0.0}) << " is " << wrap / median
        << " times longer than the median segment (" << median << ")";
      fail(m.str());
    }
  }
  grid_.build(a, b);

  // fold-back of consecutive segments (a zero-area spike) and self-intersection
  auto global_segment = [&](long g, V2<double>& p, V2<double>& q) {
    long image = 0;
    long s = g;
    if (periodic()) {
      image = static_cast<long>(std::floor(static_cast<double>(g) / nseg_));
      s = g - image * nseg_;
    }
    segment(static_cast<int>(s), image, p, q);
  };
  const long nglob = nseg_;
  for (long g = 0; g < nglob; ++g) {
    V2<double> p1, p2;
    global_segment(g, p1, p2);
    if (periodic() || g + 1 < nglob) {
      V2<double> q1, q2;
      global_segment(g + 1, q1, q2);
      const V2<double> t1 = p2 - p1, t2 = q2 - q1;
      if (std::abs(cross(t1, t2)) <= 1e-12 * norm(t1) * norm(t2) && dot(t1, t2) < 0.0)
        fail("self-intersecting: segments " + std::to_string(g) + " and " + std::to_string((g + 1) % nseg_) +
             " fold back onto each other at " + fmt(p2));
    }
    std::vector<long> images = {0};
    if (periodic()) images = {-1, 0, 1};
    for (long im : images) {
      const V2<double> shift{-static_cast<double>(im) * period_, 0.0};
      std::vector<int> cand;
      grid_.query({std::min(p1.x, p2.x) + shift.x, std::min(p1.y, p2.y)},
                  {std::max(p1.x, p2.x) + shift.x, std::max(p1.y, p2.y)}, cand);
      for (int s2 : cand) {
        const long g2 = im * nseg_ + s2;
        if (g2 == g || g2 == g + 1 || g2 == g - 1) continue;
        if (!periodic() && (g2 < 0 || g2 >= nglob)) continue;
        V2<double> q1, q2;
        segment(s2, im, q1, q2);
        if (segments_intersect(p1, p2, q1, q2))
          fail("self-intersecting: segment " + std::to_string(g) + " " + fmt(p1) + "-" + fmt(p2) + " crosses segment " +
               std::to_string(s2) + (im != 0 ? " of the neighbouring period" : "") + " " + fmt(q1) + "-" + fmt(q2));
      }
    }
  }
}

void RigidPolyline::segment(int s, long image, V2<double>& a, V2<double>& b) const {
  const double shift = static_cast<double>(image) * period_;
  a = V_[static_cast<std::size_t>(s)];
  a.x += shift;
  if (s + 1 < static_cast<int>(V_.size())) {
    b = V_[static_cast<std::size_t>(s + 1)];
    b.x += shift;
  } else {  // wrap-around segment of a periodic polyline
    b = V_.front();
    b.x += shift + period_;
  }
}

}  // namespace rf
