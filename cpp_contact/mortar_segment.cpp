#include "mortar_segment.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rf {

namespace {

template <class T>
void normals_t(const std::array<V2<T>, 4>& x, bool has_prev, bool has_next, V2<T>& na, V2<T>& nb) {
  const V2<T>& prev = has_prev ? x[0] : x[1];
  const V2<T>& next = has_next ? x[3] : x[2];
  na = normalized(right_normal(x[2] - prev));
  nb = normalized(right_normal(next - x[1]));
}

std::array<V2<D12>, 6> seed(const SlaveSegment& s, const MasterSegment& m) {
  std::array<V2<D12>, 6> X;
  for (int k = 0; k < 4; ++k)
    X[static_cast<std::size_t>(k)] = {variable12(s.x[static_cast<std::size_t>(k)].x, 2 * k),
                                      variable12(s.x[static_cast<std::size_t>(k)].y, 2 * k + 1)};
  X[4] = {variable12(m.q0.x, 8), variable12(m.q0.y, 9)};
  X[5] = {variable12(m.q1.x, 10), variable12(m.q1.y, 11)};
  return X;
}

/// F(xi) = (q - x(xi)) x n(xi) and dF/dxi for the projection of q onto the slave segment.
template <class T>
T projection_residual(const std::array<V2<T>, 4>& x, const V2<T>& na, const V2<T>& nb, const V2<T>& q, double xi) {
  const V2<T> xs = x[1] + xi * (x[2] - x[1]);
  const V2<T> n = na + xi * (nb - na);
  return cross(q - xs, n);
}

}  // namespace

void PairIntegrals::set_zero() {
  for (auto& a : gap)
    for (auto& b : a) b = constant12(0.0);
  for (auto& a : area) a = constant12(0.0);
  for (auto& a : D)
    for (auto& b : a) b = constant12(0.0);
  for (auto& a : M)
    for (auto& b : a) b = constant12(0.0);
  for (auto& a : nu) a = {constant12(0.0), constant12(0.0)};
}

void nodal_normals(const SlaveSegment& s, V2<double>& na, V2<double>& nb) {
  normals_t(s.x, s.has_prev, s.has_next, na, nb);
}

void nodal_normals(const SlaveSegment& s, const MasterSegment& m, V2<double>& na, V2<double>& nb) {
  normals_t(s.x, s.has_prev, s.has_next, na, nb);
  if (s.vertex_a) na = -1.0 * m.outward_normal();
  if (s.vertex_b) nb = -1.0 * m.outward_normal();
}

Overlap overlap(const SlaveSegment& s, const V2<double>& na, const V2<double>& nb, const MasterSegment& m) {
  // The overlap is the set of slave coordinates xi whose ray x(xi) + g n(xi) meets the master
  // segment itself, eta(xi) in [0, 1], with the master facing the slave there.  eta(xi) is a ratio
  // of a quadratic and a linear function of xi: it is monotone only while the denominator
  // cross(t, n(xi)) keeps its sign.  Where a slave segment is bent over a master feature sharper
  // than itself (its nodal normals rotate by 60 degrees and more, e.g. a peak poking through a
  // contact element), a ray becomes parallel to a steep master segment inside the slave segment,
  // and deciding from the two end projections alone (the former rule) took the wrong master node
  // and its spurious root: a neighbouring segment's true overlap was lost and a far flank's was
  // accepted, so the pieces (and the residual) jumped by a finite amount under an infinitesimal
  // displacement (issue 14: micro1, p = 15.1 MPa, residual 1.4e-4 -> 5.7e-2 across 1e-16 mm,
  // Newton stagnating).  Here every root of eta = 0 and eta = 1 in (0, 1) (both roots of each
  // quadratic) splits [0, 1]; a sub-interval is covered when eta at its midpoint lies in [0, 1],
  // so the ends move continuously with the geometry.  Disjoint covered parts keep the longest.
  Overlap o;
  const V2<double> t = m.q1 - m.q0;
  const V2<double> e = s.x[2] - s.x[1], mm = nb - na;
  struct End {
    double xi;
    Breakpoint::Kind kind;
  };
  std::array<End, 6> pts{};
  int np = 0;
  pts[static_cast<std::size_t>(np++)] = {0.0, Breakpoint::slave_start};
  pts[static_cast<std::size_t>(np++)] = {1.0, Breakpoint::slave_end};
  for (int node = 0; node < 2; ++node) {
    const V2<double>& q = node == 0 ? m.q0 : m.q1;
    // roots of (q - x(xi)) x n(xi) = 0
    const V2<double> d = q - s.x[1];
    const double c0 = cross(d, na), c1 = cross(d, mm) - cross(e, na), c2 = -cross(e, mm);
    double roots[2];
    int nr = 0;
    if (std::abs(c2) <= 1e-12 * std::max(std::abs(c1), std::abs(c0))) {
      if (c1 != 0.0) roots[nr++] = -c0 / c1;
    } else {
      const double disc = c1 * c1 - 4.0 * c2 * c0;
      if (disc >= 0.0) {
        const double sq = std::sqrt(disc);
        const double qq = -0.5 * (c1 + std::copysign(sq, c1));
        roots[nr++] = qq / c2;
        if (qq != 0.0) roots[nr++] = c0 / qq;
      }
    }
    for (int k = 0; k < nr; ++k)
      if (std::isfinite(roots[k]) && roots[k] > 0.0 && roots[k] < 1.0)
        pts[static_cast<std::size_t>(np++)] = {roots[k], node == 0 ? Breakpoint::master_q0 : Breakpoint::master_q1};
  }
  std::sort(pts.begin(), pts.begin() + np, [](const End& a, const End& b) { return a.xi < b.xi; });
  auto covered = [&](double xi) {
    const V2<double> x = s.x[1] + xi * e;
    const V2<double> n = na + xi * mm;
    const double den = cross(t, n);
    if (den == 0.0) return false;
    const double eta = cross(x - m.q0, n) / den;
    return eta >= 0.0 && eta <= 1.0 && dot(n, m.outward_normal()) < 0.0;  // meets it, facing
  };
  int best_lo = -1, best_hi = -1, run_lo = -1;
  double best_len = 0.0;
  for (int i = 0; i + 1 < np; ++i) {
    const End &a = pts[static_cast<std::size_t>(i)], &b = pts[static_cast<std::size_t>(i + 1)];
    const bool in = b.xi - a.xi > 1e-12 && covered(0.5 * (a.xi + b.xi));
    const bool skip = !(b.xi - a.xi > 1e-12);  // a repeated point: the run goes on
    if (skip) continue;
    if (in && run_lo < 0) run_lo = i;
    if (!in && run_lo >= 0) {
      const double len = a.xi - pts[static_cast<std::size_t>(run_lo)].xi;
      if (len > best_len) best_len = len, best_lo = run_lo, best_hi = i;
      run_lo = -1;
    }
  }
  if (run_lo >= 0) {
    const double len = pts[static_cast<std::size_t>(np - 1)].xi - pts[static_cast<std::size_t>(run_lo)].xi;
    if (len > best_len) best_len = len, best_lo = run_lo, best_hi = np - 1;
  }
  if (best_lo < 0 || !(best_len > 1e-12)) return o;
  o.lo = pts[static_cast<std::size_t>(best_lo)].xi;
  o.lo_kind = pts[static_cast<std::size_t>(best_lo)].kind;
  o.hi = pts[static_cast<std::size_t>(best_hi)].xi;
  o.hi_kind = pts[static_cast<std::size_t>(best_hi)].kind;
  o.valid = true;
  return o;
}

double normal_gap_at(const SlaveSegment& s, const V2<double>& na, const V2<double>& nb, const MasterSegment& m,
                     double xi) {
  const V2<double> x1 = s.x[1] + xi * (s.x[2] - s.x[1]);
  const V2<double> n = na + xi * (nb - na);
  const double den = cross(m.q1 - m.q0, n);
  if (den == 0.0) return INFINITY;
  const double eta = cross(x1 - m.q0, n) / den;
  const V2<double> x2 = m.q0 + eta * (m.q1 - m.q0);
  return dot(x2 - x1, n) / norm(n);
}

void integrate_piece(const SlaveSegment& s, const MasterSegment& m, const Breakpoint& lo, const Breakpoint& hi,
                     int n_gauss, PairIntegrals& out) {
  const std::array<V2<D12>, 6> X = seed(s, m);
  const std::array<V2<D12>, 4> xs{X[0], X[1], X[2], X[3]};
  // the master's normal seen from the slave, constant on the piece
  const V2<D12> nu2 = -1.0 * m.outward_normal(X[4], X[5]);
  V2<D12> na, nb;
  normals_t(xs, s.has_prev, s.has_next, na, nb);
  if (s.vertex_a) na = nu2;
  if (s.vertex_b) nb = nu2;

  // End points of the piece: exact values, derivatives by the implicit function theorem
  // (one Newton correction in dual numbers around the converged value).
  auto end_point = [&](const Breakpoint& bp) -> D12 {
    switch (bp.kind) {
      case Breakpoint::slave_start:
        return constant12(0.0);
      case Breakpoint::slave_end:
        return constant12(1.0);
      default:
        break;
    }
    const V2<D12> q = bp.kind == Breakpoint::master_q0   ? X[4]
                      : bp.kind == Breakpoint::master_q1 ? X[5]
                                                         : lift(bp.q, X[4].x);
    // a break point from another master segment's overlap: the vertex end's projection normal
    // is that segment's (a constant), the other end's the same averaged slave normal
    V2<D12> ea = na, eb = nb;
    if (bp.other_normal) {
      if (s.vertex_a) ea = lift(bp.vertex_normal, X[0].x);
      if (s.vertex_b) eb = lift(bp.vertex_normal, X[0].x);
    }
    const V2<double> ea_v = values(ea), eb_v = values(eb);
    const D12 F = projection_residual(xs, ea, eb, q, bp.xi);
    const V2<double> qv = values(q);
    const V2<double> xv = s.x[1] + bp.xi * (s.x[2] - s.x[1]);
    const V2<double> nv = ea_v + bp.xi * (eb_v - ea_v);
    const double dF = cross(-1.0 * (s.x[2] - s.x[1]), nv) + cross(qv - xv, eb_v - ea_v);
    D12 r = constant12(bp.xi);
    r -= F / dF;
    r.v = bp.xi;  // keep the converged value; F(xi) ~ 0 up to round-off
    return r;
  };
  const D12 xlo = end_point(lo), xhi = end_point(hi);
  const D12 len = norm(X[2] - X[1]);
  const D12 half = (xhi - xlo) * 0.5;

  const GaussRule& rule = gauss_legendre(n_gauss);
  for (std::size_t g = 0; g < static_cast<std::size_t>(rule.n); ++g) {
    const D12 xi = xlo + half * (1.0 + rule.x[g]);
    const D12 w = half * len * rule.w[g];
    const V2<D12> x1 = X[1] + xi * (X[2] - X[1]);
    const V2<D12> n = na + xi * (nb - na);
    const V2<D12> t = X[5] - X[4];
    const D12 eta = cross(x1 - X[4], n) / cross(t, n);
    const V2<D12> x2 = X[4] + eta * t;
    const V2<D12> dx = x2 - x1;
    const std::array<D12, 2> N{1.0 - xi, xi};
    const std::array<D12, 2> Nm{1.0 - eta, eta};
    for (std::size_t A = 0; A < 2; ++A) {
      const D12 MAw = N[A] * w;
      out.gap[A][0] += MAw * dx.x;
      out.gap[A][1] += MAw * dx.y;
      out.area[A] += MAw;
      out.nu[A].x += MAw * nu2.x;
      out.nu[A].y += MAw * nu2.y;
      for (std::size_t B = 0; B < 2; ++B) out.D[A][B] += MAw * N[B];
      for (std::size_t C = 0; C < 2; ++C) out.M[A][C] += MAw * Nm[C];
    }
  }
}

bool node_to_segment(const std::array<V2<double>, 3>& x, bool has_prev, bool has_next, const MasterSegment& m,
                     PairIntegrals& out, double& eta_value, double& gap_value) {
  // values first (decision), then duals
  const V2<double> prev = has_prev ? x[0] : x[1];
  const V2<double> next = has_next ? x[2] : x[1];
  const V2<double> nv = normalized(right_normal(next - prev));
  const V2<double> tv = m.q1 - m.q0;
  const double den = cross(tv, nv);
  if (den == 0.0) return false;
  const double eta = cross(x[1] - m.q0, nv) / den;
  if (eta < -1e-12 || eta > 1.0 + 1e-12) return false;
  if (!(dot(nv, m.outward_normal()) < 0.0)) return false;
  eta_value = eta;
  gap_value = dot(m.q0 + eta * tv - x[1], nv);

  SlaveSegment s;
  s.x = {x[0], x[1], x[2], x[2]};
  const std::array<V2<D12>, 6> X = seed(s, m);
  const V2<D12>& xa = X[1];
  const V2<D12>& xp = has_prev ? X[0] : X[1];
  const V2<D12>& xn = has_next ? X[2] : X[1];
  const V2<D12> n = normalized(right_normal(xn - xp));
  D12 w = constant12(0.0);
  if (has_prev) w += 0.5 * norm(X[1] - X[0]);
  if (has_next) w += 0.5 * norm(X[2] - X[1]);
  const V2<D12> t = X[5] - X[4];
  const D12 e = cross(xa - X[4], n) / cross(t, n);
  const V2<D12> x2 = X[4] + e * t;
  out.set_zero();
  out.gap[0][0] = w * (x2.x - xa.x);
  out.gap[0][1] = w * (x2.y - xa.y);
  out.area[0] = w;
  out.D[0][0] = w;
  out.M[0][0] = w * (1.0 - e);
  out.M[0][1] = w * e;
  out.nu[0] = -1.0 * (w * m.outward_normal(X[4], X[5]));
  return true;
}

// Gauss-Legendre points and weights, 21 significant digits (roots of P_n and 2/((1-x^2) P_n'(x)^2)
// computed with 50-digit arithmetic); the compiler rounds them to the nearest double.
constexpr std::array<GaussRule, kMaxGaussPoints> kGaussLegendre{{
    {1, {0.0}, {2.0}},
    {2, {0.577350269189625764509, -0.577350269189625764509}, {1.0, 1.0}},
    {3,
     {0.774596669241483377036, 0.0, -0.774596669241483377036},
     {0.555555555555555555556, 0.888888888888888888889, 0.555555555555555555556}},
    {4,
     {0.861136311594052575224, 0.339981043584856264803, -0.339981043584856264803, -0.861136311594052575224},
     {0.347854845137453857373, 0.652145154862546142627, 0.652145154862546142627, 0.347854845137453857373}},
    {5,
     {0.906179845938663992798, 0.538469310105683091036, 0.0, -0.538469310105683091036, -0.906179845938663992798},
     {0.236926885056189087514, 0.478628670499366468041, 0.568888888888888888889, 0.478628670499366468041,
      0.236926885056189087514}},
    {6,
     {0.932469514203152027812, 0.661209386466264513661, 0.238619186083196908631, -0.238619186083196908631,
      -0.661209386466264513661, -0.932469514203152027812},
     {0.171324492379170345040, 0.360761573048138607570, 0.467913934572691047390, 0.467913934572691047390,
      0.360761573048138607570, 0.171324492379170345040}},
    {7,
     {0.949107912342758524526, 0.741531185599394439864, 0.405845151377397166907, 0.0, -0.405845151377397166907,
      -0.741531185599394439864, -0.949107912342758524526},
     {0.129484966168869693271, 0.279705391489276667901, 0.381830050505118944950, 0.417959183673469387755,
      0.381830050505118944950, 0.279705391489276667901, 0.129484966168869693271}},
    {8,
     {0.960289856497536231684, 0.796666477413626739592, 0.525532409916328985818, 0.183434642495649804939,
      -0.183434642495649804939, -0.525532409916328985818, -0.796666477413626739592, -0.960289856497536231684},
     {0.101228536290376259153, 0.222381034453374470544, 0.313706645877887287338, 0.362683783378361982965,
      0.362683783378361982965, 0.313706645877887287338, 0.222381034453374470544, 0.101228536290376259153}},
}};

// each row i holds i + 1 points whose weights sum to the length 2 of [-1, 1]
constexpr bool gauss_table_consistent() {
  for (std::size_t i = 0; i < kGaussLegendre.size(); ++i) {
    const GaussRule& r = kGaussLegendre[i];
    double sum = 0.0;
    for (std::size_t g = 0; g < static_cast<std::size_t>(r.n); ++g) sum += r.w[g];
    if (r.n != static_cast<int>(i) + 1 || !(sum > 2.0 - 1e-15 && sum < 2.0 + 1e-15)) return false;
  }
  return true;
}
static_assert(gauss_table_consistent(), "Gauss-Legendre table: row i needs i + 1 points with weights summing to 2");

const GaussRule& gauss_legendre(int n) {
  if (n < kMinGaussPoints || n > kMaxGaussPoints) {
    std::ostringstream m;
    m << "Gauss points per segment piece: got " << n << ", expected " << kMinGaussPoints << " to " << kMaxGaussPoints
      << " (the orders of the Gauss-Legendre table)";
    throw std::invalid_argument(m.str());
  }
  return kGaussLegendre[static_cast<std::size_t>(n - 1)];
}

}  // namespace rf
