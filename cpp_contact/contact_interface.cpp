#include "contact_interface.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace rf {

// search boxes wider than this many master periods only come from diverged iterates
constexpr double kMaxImageSpan = 64.0;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(const Clock::time_point& t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

int local_index(const std::vector<int>& ents, int e) {
  const auto it = std::lower_bound(ents.begin(), ents.end(), e);
  return static_cast<int>(it - ents.begin());
}

/// dst += src, with src's slot s (2 coordinates) mapped to dst variables base[s], base[s] + 1.
void scatter(const D12& src, DX& dst, const std::array<int, 6>& base) {
  dst.v += src.v;
  for (int s = 0; s < 6; ++s) {
    const int b = base[static_cast<std::size_t>(s)];
    if (b < 0) continue;
    dst.d[b] += src.d[2 * s];
    dst.d[b + 1] += src.d[2 * s + 1];
  }
}

/// Grid of the segments of a deformable surface at positions x.
void build_segment_grid(const SurfaceMesh& m, const std::vector<V2<double>>& x, SegmentGrid& grid) {
  std::vector<V2<double>> a(m.segments.size()), b(m.segments.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    a[k] = x[static_cast<std::size_t>(m.segments[k][0])];
    b[k] = x[static_cast<std::size_t>(m.segments[k][1])];
  }
  grid.build(a, b);
}

DX& find_or_add(std::vector<std::pair<int, DX>>& list, int entity, Eigen::Index size) {
  for (auto& [e, v] : list)
    if (e == entity) return v;
  list.emplace_back(entity, constantX(0.0, size));
  return list.back().second;
}

}  // namespace

void NodeOutput::resize(std::size_t n) {
  status.assign(n, 0);
  paired.assign(n, 0);
  for (auto* v : {&gap, &pressure, &t_T, &dgamma, &dg_T, &velocity, &mu, &area, &q_slave, &q_master, &nx, &ny,
                  &elastic_gap, &power})
    v->assign(n, 0.0);
}

ContactInterface::ContactInterface(SurfaceMesh slave, Method method) : slave_(std::move(slave)), method_(method) {
  const std::size_t n = slave_.X.size();
  xs_n_ = slave_.X;
  ge_.assign(n, 0.0);
  out_.resize(n);
  for (const auto& d : slave_.dofs) max_dof_ = std::max({max_dof_, d[0], d[1]});
  for (const auto d : slave_.temperature_dofs) max_dof_ = std::max(max_dof_, d);
  w_ref_.assign(n, 0.0);
  for (const auto& sg : slave_.segments) {
    const double len = norm(slave_.X[static_cast<std::size_t>(sg[1])] - slave_.X[static_cast<std::size_t>(sg[0])]);
    w_ref_[static_cast<std::size_t>(sg[0])] += 0.5 * len;
    w_ref_[static_cast<std::size_t>(sg[1])] += 0.5 * len;
  }
}

void ContactInterface::set_rigid_master(RigidPolyline master) {
  forget_evaluation();
  if (master_) throw std::invalid_argument("a deformable master is already set; one master per interface");
  if (method_ == Method::node_to_surface) height_ = std::make_unique<HeightField>(master.vertices(), master.period());
  rigid_ = std::make_unique<RigidPolyline>(std::move(master));
}

void ContactInterface::set_deformable_master(SurfaceMesh master) {
  forget_evaluation();
  if (rigid_) throw std::invalid_argument("a rigid master is already set; one master per interface");
  if (method_ == Method::node_to_surface)
    throw std::invalid_argument("node-to-surface contact needs a rigid periodic master (a height field)");
  for (const auto& d : master.dofs)
    for (const auto& s : slave_.dofs)
      if (d[0] == s[0] || d[0] == s[1] || d[1] == s[0] || d[1] == s[1])
        throw std::invalid_argument("master surface: dof " + std::to_string(d[0]) + "/" + std::to_string(d[1]) +
                                    " is also a slave dof; the two bodies must have distinct dofs");
  master_ = std::make_unique<SurfaceMesh>(std::move(master));
  xm_n_ = master_->X;
  for (const auto& d : master_->dofs) max_dof_ = std::max({max_dof_, d[0], d[1]});
  for (const auto d : master_->temperature_dofs) max_dof_ = std::max(max_dof_, d);
}

void ContactInterface::set_penalty(double cN, double cT) {
  forget_evaluation();
  if (!std::isfinite(cN) || !(cN > 0.0)) {
    std::ostringstream m;
    m << "penalty c_N = " << cN << " is invalid, expected a finite value > 0 [MPa/mm]";
    throw std::invalid_argument(m.str());
  }
  if (!std::isfinite(cT) || cT < 0.0) {
    std::ostringstream m;
    m << "penalty c_T = " << cT << " is invalid, expected a finite value >= 0 [MPa/mm]";
    throw std::invalid_argument(m.str());
  }
  penalty_ = PenaltyChoice{};
  penalty_.set = true;
  penalty_.cN = cN;
  penalty_.cT = cT;
}

void ContactInterface::set_auto_penalty(double E_eff, double alpha, double tangential_fraction) {
  forget_evaluation();
  auto bad = [](const char* f, double v, const char* e) {
    std::ostringstream m;
    m << "automatic penalty: " << f << " = " << v << " is invalid, expected " << e;
    throw std::invalid_argument(m.str());
  };
  if (!std::isfinite(E_eff) || !(E_eff > 0.0)) bad("E_eff", E_eff, "the effective modulus of the slave body > 0 [MPa]");
  if (!std::isfinite(alpha) || !(alpha > 0.0)) bad("alpha", alpha, "a factor > 0");
  if (!std::isfinite(tangential_fraction) || tangential_fraction < 0.0)
    bad("tangential_fraction", tangential_fraction, "a fraction >= 0");
  double h = slave_.h_min;
  if (master_) h = std::min(h, master_->h_min);
  penalty_ = PenaltyChoice{};
  penalty_.set = true;
  penalty_.automatic = true;
  penalty_.alpha = alpha;
  penalty_.tangential_fraction = tangential_fraction;
  penalty_.E_eff = E_eff;
  penalty_.h = h;
  penalty_.cN = alpha * E_eff / h;
  penalty_.cT = tangential_fraction * penalty_.cN;
}

void ContactInterface::set_thermal(const ThermalParameters& t) {
  forget_evaluation();
  t.validate();
  thermal_ = t;
}

void ContactInterface::set_slave_temperatures(std::vector<double> T) {
  forget_evaluation();
  if (!T.empty() && T.size() != slave_.X.size())
    throw std::invalid_argument("slave temperatures: " + std::to_string(T.size()) + " values for " +
                                std::to_string(slave_.X.size()) + " slave nodes");
  for (const double v : T)
    if (!std::isfinite(v) || v <= 0.0)
      throw std::invalid_argument("slave temperatures: " + std::to_string(v) + " K is not a temperature > 0 K");
  slave_T_ = std::move(T);
}

void ContactInterface::set_fixed_dofs(std::vector<DofIndex> dofs) {
  forget_evaluation();
  std::sort(dofs.begin(), dofs.end());
  dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
  fixed_ = std::move(dofs);
}

bool ContactInterface::is_fixed(DofIndex d) const { return std::binary_search(fixed_.begin(), fixed_.end(), d); }

void ContactInterface::set_search_radius(double r) {
  forget_evaluation();
  if (!std::isfinite(r) || !(r > 0.0)) {
    std::ostringstream m;
    m << "search radius = " << r << " is invalid, expected a finite distance > 0 [mm]";
    throw std::invalid_argument(m.str());
  }
  search_radius_ = r;
}

void ContactInterface::set_gauss_points(int n) {
  forget_evaluation();
  gauss_legendre(n);  // validates n against the table
  n_gauss_ = n;
}

double ContactInterface::search_radius() const { return search_radius_ > 0.0 ? search_radius_ : 2.0 * slave_.h_max; }

void ContactInterface::positions(const double* u, std::size_t n, std::vector<V2<double>>& xs,
                                 std::vector<V2<double>>& xm) const {
  if (max_dof_ >= 0 && static_cast<std::size_t>(max_dof_) >= n) {
    std::ostringstream m;
    m << "solution array has " << n << " entries but the contact refers to dof " << max_dof_;
    throw std::invalid_argument(m.str());
  }
  xs.resize(slave_.X.size());
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const auto& d = slave_.dofs[i];
    xs[i] = {slave_.X[i].x + u[d[0]], slave_.X[i].y + u[d[1]]};
    if (!std::isfinite(xs[i].x) || !std::isfinite(xs[i].y))
      throw std::invalid_argument("non-finite displacement at slave node " + std::to_string(i));
  }
  xm.clear();
  if (master_) {
    xm.resize(master_->X.size());
    for (std::size_t i = 0; i < xm.size(); ++i) {
      const auto& d = master_->dofs[i];
      xm[i] = {master_->X[i].x + u[d[0]], master_->X[i].y + u[d[1]]};
      if (!std::isfinite(xm[i].x) || !std::isfinite(xm[i].y))
        throw std::invalid_argument("non-finite displacement at master node " + std::to_string(i));
    }
  }
}

void ContactInterface::reset_history(const double* u, std::size_t n, const V2<double>& offset) {
  forget_evaluation();
  positions(u, n, xs_n_, xm_n_);
  offset_n_ = offset;
  std::fill(ge_.begin(), ge_.end(), 0.0);
}

void ContactInterface::set_elastic_gap(const std::vector<double>& gap) {
  forget_evaluation();
  if (gap.size() != ge_.size())
    throw std::invalid_argument("set_elastic_gap: " + std::to_string(gap.size()) + " values for " +
                                std::to_string(ge_.size()) + " slave nodes");
  ge_ = gap;
}

MasterSegment ContactInterface::master_segment(const MasterRef& m) const {
  MasterSegment s;
  if (rigid_) {
    rigid_->segment(m.seg, m.image, s.q0, s.q1);
    s.q0 = s.q0 + offset_;
    s.q1 = s.q1 + offset_;
    s.normal_sign = -1.0;
  } else {
    const auto& sg = master_->segments[static_cast<std::size_t>(m.seg)];
    s.q0 = xm_[static_cast<std::size_t>(sg[0])];
    s.q1 = xm_[static_cast<std::size_t>(sg[1])];
    s.normal_sign = 1.0;
  }
  return s;
}

std::array<int, 2> ContactInterface::master_nodes(const MasterRef& m) const {
  if (rigid_) return {-1, -1};
  return master_->segments[static_cast<std::size_t>(m.seg)];
}

void ContactInterface::candidates(const V2<double>& lo, const V2<double>& hi, std::vector<MasterRef>& out) const {
  out.clear();
  std::vector<int> ids;
  if (rigid_) {
    const V2<double> l = lo - offset_, h = hi - offset_;
    const SegmentGrid& g = rigid_->grid();
    if (rigid_->periodic()) {
      const double L = rigid_->period();
      // a diverged Newton iterate can fling a slave node far away (or to NaN): such a box has no
      // meaningful candidates, and looping over its images would not end; the bulk residual of
      // that iterate reports the divergence
      if (!std::isfinite(l.x) || !std::isfinite(h.x) || !std::isfinite(l.y) || !std::isfinite(h.y) ||
          h.x - l.x > kMaxImageSpan * L)
        return;
      const long k0 = static_cast<long>(std::floor((l.x - g.upper().x) / L));
      const long k1 = static_cast<long>(std::ceil((h.x - g.lower().x) / L));
      for (long k = k0; k <= k1; ++k) {
        ids.clear();
        const double sh = static_cast<double>(k) * L;
        g.query({l.x - sh, l.y}, {h.x - sh, h.y}, ids);
        for (int s : ids) out.push_back({k, s});
      }
    } else {
      g.query(l, h, ids);
      for (int s : ids) out.push_back({0, s});
    }
  } else {
    master_grid_.query(lo, hi, ids);
    for (int s : ids) out.push_back({0, s});
  }
}

SlaveSegment ContactInterface::slave_segment(int e) const {
  const auto& sg = slave_.segments[static_cast<std::size_t>(e)];
  const int a = sg[0], b = sg[1];
  const int p = slave_.prev[static_cast<std::size_t>(a)], q = slave_.next[static_cast<std::size_t>(b)];
  SlaveSegment s;
  s.has_prev = p >= 0;
  s.has_next = q >= 0;
  s.vertex_a = rigid_ && vertex_end(a);  // deformable master: see SlaveSegment::vertex_a
  s.vertex_b = rigid_ && vertex_end(b);
  s.x = {xs_[static_cast<std::size_t>(s.has_prev ? p : a)], xs_[static_cast<std::size_t>(a)],
         xs_[static_cast<std::size_t>(b)], xs_[static_cast<std::size_t>(s.has_next ? q : b)]};
  return s;
}

void ContactInterface::search_mortar(std::vector<PairRecord>& pairs) const {
  const double r = search_radius();
  const double R = 1.5 * r;
  const double tol = 1e-12;
  struct Cand {
    MasterRef ref;
    MasterSegment seg;
    Overlap ov;
    std::array<int, 2> nodes;
    V2<double> na, nb;  // projection normals at a and b against this master segment
  };
  std::vector<MasterRef> refs;
  std::vector<Cand> cands;
  std::vector<double> bps;
  for (int e = 0; e < static_cast<int>(slave_.segments.size()); ++e) {
    const SlaveSegment s = slave_segment(e);
    V2<double> na, nb;
    nodal_normals(s, na, nb);
    V2<double> lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
    for (const V2<double>& p : {s.x[1] + R * na, s.x[1] - R * na, s.x[2] + R * nb, s.x[2] - R * nb}) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    }
    // a vertex end projects along the master's normal, whatever its direction: search around it
    for (int k = 1; k <= 2; ++k) {
      if (!(k == 1 ? s.vertex_a : s.vertex_b)) continue;
      const V2<double>& p = s.x[static_cast<std::size_t>(k)];
      lo = {std::min(lo.x, p.x - R), std::min(lo.y, p.y - R)};
      hi = {std::max(hi.x, p.x + R), std::max(hi.y, p.y + R)};
    }
    candidates(lo, hi, refs);
    cands.clear();
    for (const MasterRef& ref : refs) {
      Cand c{ref, master_segment(ref), Overlap{}, master_nodes(ref), na, nb};
      nodal_normals(s, c.seg, c.na, c.nb);
      c.ov = overlap(s, c.na, c.nb, c.seg);
      if (c.ov.valid) cands.push_back(c);
    }
    if (cands.empty()) continue;
    bps.clear();
    for (const Cand& c : cands) {
      bps.push_back(c.ov.lo);
      bps.push_back(c.ov.hi);
    }
    std::sort(bps.begin(), bps.end());
    // choose, on every elementary interval, the candidate with the smallest |gap| (within r)
    struct Piece {
      int cand;
      double lo, hi;
    };
    std::vector<Piece> pieces;
    for (std::size_t i = 0; i + 1 < bps.size(); ++i) {
      const double a = bps[i], b = bps[i + 1];
      if (!(b - a > tol)) continue;
      const double mid = 0.5 * (a + b);
      int best = -1;
      double best_abs = INFINITY;
      for (std::size_t k = 0; k < cands.size(); ++k) {
        const Cand& c = cands[k];
        if (mid < c.ov.lo || mid > c.ov.hi) continue;
        const double g = normal_gap_at(s, c.na, c.nb, c.seg, mid);
        if (!(std::abs(g) <= r)) continue;
        if (std::abs(g) < best_abs) {
          best_abs = std::abs(g);
          best = static_cast<int>(k);
        }
      }
      if (best < 0) continue;
      if (!pieces.empty() && pieces.back().cand == best && std::abs(pieces.back().hi - a) <= 1e-10)
        pieces.back().hi = b;
      else
        pieces.push_back({best, a, b});
    }
    for (const Piece& pc : pieces) {
      const Cand& c = cands[static_cast<std::size_t>(pc.cand)];
      auto make_bp = [&](double xi) {
        Breakpoint bp;
        bp.xi = xi;
        if (std::abs(xi - c.ov.lo) <= tol) {
          bp.kind = c.ov.lo_kind;
          bp.xi = c.ov.lo;
          return bp;
        }
        if (std::abs(xi - c.ov.hi) <= tol) {
          bp.kind = c.ov.hi_kind;
          bp.xi = c.ov.hi;
          return bp;
        }
        // an end point of another candidate (overlapping projections)
        for (const Cand& o : cands) {
          for (int end = 0; end < 2; ++end) {
            const double v = end == 0 ? o.ov.lo : o.ov.hi;
            const Breakpoint::Kind k = end == 0 ? o.ov.lo_kind : o.ov.hi_kind;
            if (std::abs(v - xi) > tol) continue;
            if (k == Breakpoint::slave_start || k == Breakpoint::slave_end) {
              bp.kind = k;
              bp.xi = v;
              return bp;
            }
            const int node = k == Breakpoint::master_q0 ? o.nodes[0] : o.nodes[1];
            const V2<double> q = k == Breakpoint::master_q0 ? o.seg.q0 : o.seg.q1;
            bp.xi = v;
            if (s.vertex_a || s.vertex_b) {  // projected along o's normal at the vertex
              bp.other_normal = true;
              bp.vertex_normal = s.vertex_a ? o.na : o.nb;
            }
            if (node >= 0 && node == c.nodes[0])
              bp.kind = Breakpoint::master_q0;
            else if (node >= 0 && node == c.nodes[1])
              bp.kind = Breakpoint::master_q1;
            else {
              bp.kind = Breakpoint::foreign;
              bp.q = q;
            }
            return bp;
          }
        }
        throw std::logic_error("mortar segmentation: unmatched break point");
      };
      PairRecord pr;
      pr.slave = e;
      pr.master = c.ref;
      pr.lo = make_bp(pc.lo);
      pr.hi = make_bp(pc.hi);
      pairs.push_back(pr);
    }
  }
}

void ContactInterface::search_nts(std::vector<PairRecord>& pairs) const {
  const double r = search_radius();
  const double R = 1.5 * r;
  std::vector<MasterRef> refs;
  for (int A = 0; A < slave_.num_nodes(); ++A) {
    const int p = slave_.prev[static_cast<std::size_t>(A)], q = slave_.next[static_cast<std::size_t>(A)];
    const V2<double> x = xs_[static_cast<std::size_t>(A)];
    const V2<double> xp = p >= 0 ? xs_[static_cast<std::size_t>(p)] : x;
    const V2<double> xn = q >= 0 ? xs_[static_cast<std::size_t>(q)] : x;
    const V2<double> n = normalized(right_normal(xn - xp));
    const V2<double> a = x + R * n, b = x - R * n;
    candidates({std::min(a.x, b.x), std::min(a.y, b.y)}, {std::max(a.x, b.x), std::max(a.y, b.y)}, refs);
    int best = -1;
    double best_abs = INFINITY;
    for (std::size_t k = 0; k < refs.size(); ++k) {
      const MasterSegment m = master_segment(refs[k]);
      const V2<double> t = m.q1 - m.q0;
      const double den = cross(t, n);
      if (den == 0.0) continue;
      const double eta = cross(x - m.q0, n) / den;
      if (eta < -1e-12 || eta > 1.0 + 1e-12) continue;
      if (!(dot(n, m.outward_normal()) < 0.0)) continue;
      const double g = dot(m.q0 + eta * t - x, n);
      if (!(std::abs(g) <= r)) continue;
      if (std::abs(g) < best_abs) {
        best_abs = std::abs(g);
        best = static_cast<int>(k);
      }
    }
    if (best < 0) continue;
    PairRecord pr;
    pr.slave = A;
    pr.master = refs[static_cast<std::size_t>(best)];
    pairs.push_back(pr);
  }
}

// node_to_surface search: every slave node within the search radius of the height field (gap
// g = (z - h(x)) / sqrt(1 + h'^2) at the node's x, rigid offset applied) is paired; there is
// nothing else to find, the surface is a function of x.
void ContactInterface::search_surface(std::vector<PairRecord>& pairs) const {
  const double r = search_radius();
  for (int A = 0; A < slave_.num_nodes(); ++A) {
    const V2<double> x = xs_[static_cast<std::size_t>(A)];
    const HeightValue hv = (*height_)(x.x - offset_.x);
    const double g = (x.y - offset_.y - hv.h) / std::sqrt(1.0 + hv.d1 * hv.d1);
    if (!(g <= r)) continue;
    PairRecord pr;
    pr.slave = A;
    pairs.push_back(pr);
  }
}

// node_to_surface integrals of slave node A: with s = x - o_x, phi = z - o_z - h(s) and
// m = sqrt(1 + h'(s)^2), the gap g = phi / m (the normal distance to first order in phi, smooth
// in the node's position wherever h is), the frame n_A = -grad g (unit on the surface), the
// constant reference weight w_A (half the adjacent reference segments) as A_A and D_AA, and
// gbar_A = w_A g n_A / |n_A|^2, so that the nodal law's g_A = gbar_A . n_A / A_A is g. The law's
// P_A = p_A n_A then makes R_A = w_A P_A = d/dx_A (w_A c_N <-g_A>^2 / 2): the residual is a
// gradient and its tangent (second derivatives of g through h'', h''') is symmetric.
void ContactInterface::surface_integrals(int A, const Stencil& L, NodalIntegrals& a) const {
  const std::size_t iA = static_cast<std::size_t>(A);
  const Eigen::Index S = stride() * static_cast<Eigen::Index>(L.size());
  const V2<DX> x = position_dual(L, A);
  const HeightValue hv = (*height_)(x.x.v - offset_.x);
  const DX ds = x.x - x.x.v;  // dual offset of x from where h was evaluated (value 0)
  const DX h = hv.h + hv.d1 * ds, h1 = hv.d1 + hv.d2 * ds, h2 = hv.d2 + hv.d3 * ds;
  const DX phi = x.y - offset_.y - h;
  const DX m = sqrt(1.0 + h1 * h1);
  const DX g = phi / m;
  a.frame = {h1 / m + phi * h1 * h2 / (m * m * m), -1.0 / m};
  const double w = w_ref_[iA];
  const DX nn = a.frame.x * a.frame.x + a.frame.y * a.frame.y;
  a.area = constantX(w, S);
  a.gx = w * g * a.frame.x / nn;
  a.gy = w * g * a.frame.y / nn;
  a.D.clear();
  a.D.emplace_back(A, constantX(w, S));
  double wc = 0.0;
  for (int e : {prev_node(A), next_node(A)})
    if (e >= 0) wc += 0.5 * norm(xs_[static_cast<std::size_t>(e)] - xs_[iA]);
  a.current_weight = wc;
}

void ContactInterface::check_ready(std::size_t n, double dt) const {
  if (!rigid_ && !master_)
    throw std::invalid_argument("no master surface: call set_rigid_master(...) or set_deformable_master(...)");
  if (!penalty_.set)
    throw std::invalid_argument(
        "no penalty parameters: call set_auto_penalty(E_eff, ...) (default) or set_penalty(c_N, c_T)");
  if (friction_ && !(penalty_.cT > 0.0))
    throw std::invalid_argument("friction needs a tangential penalty c_T > 0 (got c_T = 0)");
  if (!std::isfinite(dt) || dt < 0.0) throw std::invalid_argument("dt must be finite and >= 0");
  if (friction_ && friction_->depends_on_velocity() && !(dt > 0.0))
    throw std::invalid_argument("the friction law depends on the sliding velocity: dt must be > 0");
  if (thermal_.enabled) {
    if (!slave_.has_temperature())
      throw std::invalid_argument("thermal contact needs temperature dofs on the slave surface");
    if (master_ && !master_->has_temperature())
      throw std::invalid_argument("thermal contact with a deformable master needs temperature dofs on the master");
    if (friction_ && !(dt > 0.0)) throw std::invalid_argument("frictional heating needs dt > 0");
  }
  (void)n;
}

// evaluate() runs five phases on plain data; each one below says what it does and which thesis
// equations it implements. Discrete decisions (pairing, pieces, active/stick/slip) are taken on
// values; every continuous quantity is a dual number, so the blocks carry the exact tangent.
void ContactInterface::evaluate(const double* u, std::size_t n, const V2<double>& offset, double dt, double T_ref,
                                bool with_blocks) {
  check_ready(n, dt);
  if (!std::isfinite(offset.x) || !std::isfinite(offset.y))
    throw std::invalid_argument("rigid master offset must be finite");
  ++evaluations_;
  if (repeats_last(u, n, offset, dt, T_ref, with_blocks)) {
    ++reused_evaluations_;  // blocks_, out_ and totals_ are this evaluation's already
    return;
  }
  forget_evaluation();  // until this one completes (a throw below leaves partial outputs)
  const auto t0 = Clock::now();
  const std::vector<PairRecord> pairs = search(u, n, offset);  // 1
  last_pairs_.clear();
  for (const PairRecord& pr : pairs)
    last_pairs_.push_back({double(pr.slave), double(pr.master.image), double(pr.master.seg), pr.lo.xi, pr.hi.xi,
                           10.0 * double(pr.lo.kind) + double(pr.hi.kind)});
  const double t_search = seconds_since(t0);
  const auto t1 = Clock::now();
  const Stencils st = stencils(pairs);                                 // 2
  const std::vector<NodalIntegrals> integrals = integrate(pairs, st);  // 3

  blocks_.clear();
  const int ns = slave_.num_nodes();
  out_.resize(static_cast<std::size_t>(ns));
  InterfaceTotals tot;
  tot.n_pairs = static_cast<int>(pairs.size());
  tot.time_search = t_search;
  const LawParameters par = law_parameters(dt);
  for (int A = 0; A < ns; ++A) {
    const std::size_t iA = static_cast<std::size_t>(A);
    const Stencil& L = st.nodes[iA];
    const NodalIntegrals& a = integrals[iA];
    out_.gap[iA] = std::numeric_limits<double>::quiet_NaN();
    if (L.empty() || !(a.area.v > 0.0)) continue;
    const NodalKinematics kin = nodal_kinematics(A, L, a, u, T_ref);  // 4
    const NodalResponse resp = evaluate_nodal_law(kin, ge_[iA], par);
    record_node(A, a, kin, resp, dt, tot);
    if (with_blocks && resp.status != open) blocks_.push_back(local_block(L, a, resp));  // 5
  }
  tot.time_integration = seconds_since(t1);
  totals_ = tot;
  evaluated_ = true;
  last_.u.assign(u, u + n);
  last_.offset = offset;
  last_.dt = dt;
  last_.T_ref = T_ref;
  last_.with_blocks = with_blocks;
  last_.valid = true;
}

bool ContactInterface::repeats_last(const double* u, std::size_t n, const V2<double>& offset, double dt, double T_ref,
                                    bool with_blocks) const {
  const auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };
  return last_.valid && (last_.with_blocks || !with_blocks) && last_.u.size() == n && offset.x == last_.offset.x &&
         offset.y == last_.offset.y && dt == last_.dt && same(T_ref, last_.T_ref) &&
         std::equal(u, u + n, last_.u.begin());
}

// Phase 1, search: current positions at u, the master's segment grid, and the pairs. Mortar:
// per slave segment the master segments whose projections along the nodal normals (5.36) overlap
// it, cut into pieces with one master segment each (smallest |gap| where projections overlap).
// Node-to-segment: per slave node the master segment its normal projection falls on.
std::vector<ContactInterface::PairRecord> ContactInterface::search(const double* u, std::size_t n,
                                                                   const V2<double>& offset) {
  positions(u, n, xs_, xm_);
  offset_ = offset;
  if (master_) build_segment_grid(*master_, xm_, master_grid_);
  std::vector<PairRecord> pairs;
  if (method_ == Method::mortar)
    search_mortar(pairs);
  else if (method_ == Method::node_to_surface)
    search_surface(pairs);
  else
    search_nts(pairs);
  return pairs;
}

ContactInterface::PairSlots ContactInterface::pair_slots(const PairRecord& pr) const {
  PairSlots p;
  if (method_ == Method::mortar) {
    const auto& sg = slave_.segments[static_cast<std::size_t>(pr.slave)];
    p.entity[0] = prev_node(sg[0]);
    p.entity[1] = sg[0];
    p.entity[2] = sg[1];
    p.entity[3] = next_node(sg[1]);
    p.receivers = {sg[0], sg[1]};
    p.n_receivers = 2;
  } else if (method_ == Method::node_to_surface) {
    p.entity[1] = pr.slave;
    p.receivers = {pr.slave, -1};
    p.n_receivers = 1;
    return p;
  } else {
    p.entity[0] = prev_node(pr.slave);
    p.entity[1] = pr.slave;
    p.entity[2] = next_node(pr.slave);
    p.receivers = {pr.slave, -1};
    p.n_receivers = 1;
  }
  const std::array<int, 2> mn = master_nodes(pr.master);
  if (mn[0] >= 0) {
    const int ns = slave_.num_nodes();
    p.entity[4] = ns + mn[0];
    p.entity[5] = ns + mn[1];
  }
  return p;
}

// Phase 2, stencils: the slots of every pair and, per slave node, the entities its quantities
// depend on: the slots of its pairs (slave A-2..A+2 through the averaged normals of 5.36, the
// nodes of the paired master segments) and its own neighbours (n_A). Bookkeeping only.
ContactInterface::Stencils ContactInterface::stencils(const std::vector<PairRecord>& pairs) const {
  const int ns = slave_.num_nodes();
  Stencils st;
  st.pairs.reserve(pairs.size());
  st.nodes.resize(static_cast<std::size_t>(ns));
  for (const PairRecord& pr : pairs) {
    const PairSlots& ps = st.pairs.emplace_back(pair_slots(pr));
    for (int k = 0; k < ps.n_receivers; ++k) {
      Stencil& L = st.nodes[static_cast<std::size_t>(ps.receivers[static_cast<std::size_t>(k)])];
      for (int e : ps.entity)
        if (e >= 0) L.push_back(e);
    }
  }
  for (int A = 0; A < ns; ++A) {
    Stencil& L = st.nodes[static_cast<std::size_t>(A)];
    if (L.empty()) continue;
    if (method_ != Method::node_to_surface)  // n_A of 5.36 depends on the neighbours
      for (int e : {prev_node(A), A, next_node(A)})
        if (e >= 0) L.push_back(e);
    std::sort(L.begin(), L.end());
    L.erase(std::unique(L.begin(), L.end()), L.end());
  }
  return st;
}

// Phase 3, integration: per pair the mortar integrals gbar_A = Int M_A (x2 - x1) da,
// A_A = Int M_A da, D_AB = Int M_A N_B da, M_AC = Int M_A N_C da over its piece (5.33-5.38, Gauss
// points on the slave), or their node-to-segment collocation at the slave node; summed per
// receiving slave node.
std::vector<ContactInterface::NodalIntegrals> ContactInterface::integrate(const std::vector<PairRecord>& pairs,
                                                                          const Stencils& st) const {
  const int ns = slave_.num_nodes();
  std::vector<NodalIntegrals> acc(static_cast<std::size_t>(ns));
  for (int A = 0; A < ns; ++A) {
    const Stencil& L = st.nodes[static_cast<std::size_t>(A)];
    if (L.empty()) continue;
    const Eigen::Index S = stride() * static_cast<Eigen::Index>(L.size());
    NodalIntegrals& a = acc[static_cast<std::size_t>(A)];
    a.gx = constantX(0.0, S);
    a.gy = constantX(0.0, S);
    a.area = constantX(0.0, S);
    if (master_frame_node(A)) a.nu = {constantX(0.0, S), constantX(0.0, S)};
  }
  if (method_ == Method::node_to_surface) {
    for (const PairRecord& pr : pairs)
      surface_integrals(pr.slave, st.nodes[static_cast<std::size_t>(pr.slave)],
                        acc[static_cast<std::size_t>(pr.slave)]);
    return acc;
  }
  PairIntegrals pi;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const PairRecord& pr = pairs[i];
    const PairSlots& ps = st.pairs[i];
    const MasterSegment ms = master_segment(pr.master);
    if (method_ == Method::mortar) {
      pi.set_zero();
      integrate_piece(slave_segment(pr.slave), ms, pr.lo, pr.hi, n_gauss_, pi);
    } else {
      const int A = pr.slave;
      const int p = ps.entity[0], q = ps.entity[2];
      const std::array<V2<double>, 3> x{xs_[static_cast<std::size_t>(p >= 0 ? p : A)], xs_[static_cast<std::size_t>(A)],
                                        xs_[static_cast<std::size_t>(q >= 0 ? q : A)]};
      double eta = 0.0, g = 0.0;
      if (!node_to_segment(x, p >= 0, q >= 0, ms, pi, eta, g)) continue;
    }
    for (int k = 0; k < ps.n_receivers; ++k) {
      const int A = ps.receivers[static_cast<std::size_t>(k)];
      scatter_pair(pi, ps, k, st.nodes[static_cast<std::size_t>(A)], acc[static_cast<std::size_t>(A)]);
    }
  }
  return acc;
}

/// Adds the integrals of receiver k (its row of `pi`) to node integrals `a` over stencil L.
void ContactInterface::scatter_pair(const PairIntegrals& pi, const PairSlots& ps, int k, const Stencil& L,
                                    NodalIntegrals& a) const {
  const std::array<int, 6>& ent = ps.entity;
  const Eigen::Index S = stride() * static_cast<Eigen::Index>(L.size());
  std::array<int, 6> base;
  for (std::size_t s = 0; s < 6; ++s) base[s] = ent[s] >= 0 ? stride() * local_index(L, ent[s]) : -1;
  const std::size_t r = static_cast<std::size_t>(k);
  scatter(pi.gap[r][0], a.gx, base);
  scatter(pi.gap[r][1], a.gy, base);
  scatter(pi.area[r], a.area, base);
  if (master_frame_node(ps.receivers[r])) {
    scatter(pi.nu[r].x, a.nu.x, base);
    scatter(pi.nu[r].y, a.nu.y, base);
  }
  if (method_ == Method::mortar) {
    scatter(pi.D[r][0], find_or_add(a.D, ent[1], S), base);
    scatter(pi.D[r][1], find_or_add(a.D, ent[2], S), base);
  } else {
    scatter(pi.D[0][0], find_or_add(a.D, ent[1], S), base);
  }
  if (ent[4] >= 0) {
    scatter(pi.M[r][0], find_or_add(a.M, ent[4], S), base);
    scatter(pi.M[r][1], find_or_add(a.M, ent[5], S), base);
  }
}

// Phase 4a, nodal kinematics: the nodal frame n_A, tau_A of 5.39-5.41, the weighted slip
// increment sum_B D_AB (x_B - x_B^n) - sum_C M_AC (x_C - x_C^n) of the step (rigid master: A_A
// times its offset increment), the temperature for mu(p, v, T), and the weighted thermal gap
// sum_C M_AC theta_C - sum_B D_AB theta_B of the conduction (4.24-4.26).
//
// n_A is the averaged slave normal of 5.36, n_A ⟂ x_{A+1} - x_{A-1}, wherever the node has two
// slave neighbours (at the seam of a periodic cell, one-sided; see vertex_end). Any other chain
// end has one adjacent slave segment and nothing to average: it is a
// vertex of the slave touching the master's face, and the normal of a vertex-to-face contact is
// the face's. Its frame is the master's normal averaged over the node's support,
// n_A = Int M_A nu2 da / |Int M_A nu2 da| (nu2 = -(outward master normal)), the direction along
// which the master pushes and along whose tangent the node slides (4.2, 4.5). The one-sided normal
// of the end segment instead turns with the segment: under the pressure peak of a sharp corner the
// end node penetrates and its neighbour lifts, the end segment tilts by 5-15 degrees, and
// p_A n_A + t_T tau_A then puts part of the pressure into F_x and part of the friction into F_z
// (the 20 x 8 mm block of verify sliding-block slid at 0.966 mu, and the bias grows under refinement).
// set_master_frame(true) gives every node the master's frame (README: "Master frame for every node").
NodalKinematics ContactInterface::nodal_kinematics(int A, const Stencil& L, const NodalIntegrals& a, const double* u,
                                                   double T_ref) const {
  const int ns = slave_.num_nodes();
  const Eigen::Index S = stride() * static_cast<Eigen::Index>(L.size());
  NodalKinematics kin;
  kin.gx = a.gx;
  kin.gy = a.gy;
  kin.area = a.area;
  if (method_ == Method::node_to_surface) {
    kin.normal = a.frame;
  } else if (master_frame_node(A) && norm(values(a.nu)) > 0.0) {
    kin.normal = normalized(a.nu);
  } else {
    const int p = prev_node(A), q = next_node(A);
    const V2<DX> xp = position_dual(L, p >= 0 ? p : A), xn = position_dual(L, q >= 0 ? q : A);
    kin.normal = normalized(right_normal(xn - xp));
  }
  kin.slip_x = constantX(0.0, S);
  kin.slip_y = constantX(0.0, S);
  if (friction_) {
    for (const auto& [B, DAB] : a.D) {
      const V2<DX> x = position_dual(L, B);
      const V2<double> xn = xs_n_[static_cast<std::size_t>(B)];
      kin.slip_x += DAB * (x.x - xn.x);
      kin.slip_y += DAB * (x.y - xn.y);
    }
    if (master_) {
      for (const auto& [C, MAC] : a.M) {
        const V2<DX> x = position_dual(L, C);
        const V2<double> xn = xm_n_[static_cast<std::size_t>(C - ns)];
        kin.slip_x -= MAC * (x.x - xn.x);
        kin.slip_y -= MAC * (x.y - xn.y);
      }
    } else {
      kin.slip_x -= a.area * (offset_.x - offset_n_.x);
      kin.slip_y -= a.area * (offset_.y - offset_n_.y);
    }
  }
  const double T_node = slave_T_.empty() ? T_ref : slave_T_[static_cast<std::size_t>(A)];
  kin.temperature = slave_.has_temperature() ? temperature_dual(L, A, u) : constantX(T_node, S);
  kin.thermal_gap = constantX(0.0, S);
  if (conduction_possible()) {
    for (const auto& [B, DAB] : a.D) kin.thermal_gap -= DAB * temperature_dual(L, B, u);
    if (master_)
      for (const auto& [C, MAC] : a.M) kin.thermal_gap += MAC * temperature_dual(L, C, u);
    else
      kin.thermal_gap += a.area * thermal_.master_temperature;
  }
  return kin;
}

// Phase 4b (after the nodal law of nodal_contact_law.hpp: p_A (5.39), Coulomb return mapping
// (4.17, 4.18, 5.40), heat fluxes (4.26, 5.44, 5.45)): per node outputs and the interface totals.
void ContactInterface::record_node(int A, const NodalIntegrals& a, const NodalKinematics& kin,
                                   const NodalResponse& resp, double dt, InterfaceTotals& tot) {
  const std::size_t iA = static_cast<std::size_t>(A);
  out_.paired[iA] = 1;
  out_.status[iA] = resp.status;
  out_.gap[iA] = resp.gap;
  out_.pressure[iA] = resp.pressure;
  out_.t_T[iA] = resp.t_T;
  out_.dgamma[iA] = resp.dgamma;
  out_.dg_T[iA] = resp.dg_T;
  out_.velocity[iA] = resp.velocity;
  out_.mu[iA] = resp.mu;
  out_.area[iA] = a.area.v;
  out_.power[iA] = resp.friction_power;
  out_.nx[iA] = kin.normal.x.v;
  out_.ny[iA] = kin.normal.y.v;
  out_.elastic_gap[iA] = resp.status == open ? 0.0 : resp.elastic_gap;
  ++tot.n_paired;
  if (resp.status == open) return;
  ++tot.n_active;
  if (resp.status == stick) ++tot.n_stick;
  if (resp.status == slip) ++tot.n_slip;
  tot.contact_length += method_ == Method::node_to_surface ? a.current_weight : a.area.v;
  tot.force_x -= a.area.v * resp.P.x.v;
  tot.force_z -= a.area.v * resp.P.y.v;
  tot.friction_power += a.area.v * resp.friction_power;
  tot.dissipation += a.area.v * resp.friction_power * dt;
  if (resp.has_heat) {
    out_.q_slave[iA] = resp.q_slave.v;
    out_.q_master[iA] = resp.q_master.v;
    tot.heat_slave += a.area.v * resp.q_slave.v;
    tot.heat_master += a.area.v * resp.q_master.v;
  }
}

// Phase 5, local block of a node in contact: the penalty vector P_A distributed with the mortar
// matrices of 5.33-5.38, rows R_B += D_AB P_A (slave), R_C -= M_AC P_A (master), and the thermal
// rows R_thetaB -= D_AB q_slave, R_thetaC -= M_AC q_master (5.44, 5.45); the columns are the
// node's stencil, the entries the gradients of the rows (the exact tangent).
LocalBlock ContactInterface::local_block(const Stencil& L, const NodalIntegrals& a, const NodalResponse& resp) const {
  const int ns = slave_.num_nodes();
  LocalBlock blk;
  std::vector<DX> store;
  store.reserve(3 * (a.D.size() + a.M.size()));
  for (const auto& [B, DAB] : a.D) {
    const auto& d = slave_.dofs[static_cast<std::size_t>(B)];
    store.push_back(DAB * resp.P.x);
    blk.rows.push_back(d[0]);
    store.push_back(DAB * resp.P.y);
    blk.rows.push_back(d[1]);
  }
  if (master_) {
    for (const auto& [C, MAC] : a.M) {
      const auto& d = master_->dofs[static_cast<std::size_t>(C - ns)];
      store.push_back(-(MAC * resp.P.x));
      blk.rows.push_back(d[0]);
      store.push_back(-(MAC * resp.P.y));
      blk.rows.push_back(d[1]);
    }
  }
  if (resp.has_heat) {
    for (const auto& [B, DAB] : a.D) {
      store.push_back(-(DAB * resp.q_slave));
      blk.rows.push_back(slave_.temperature_dofs[static_cast<std::size_t>(B)]);
    }
    if (master_ && master_->has_temperature()) {
      for (const auto& [C, MAC] : a.M) {
        store.push_back(-(MAC * resp.q_master));
        blk.rows.push_back(master_->temperature_dofs[static_cast<std::size_t>(C - ns)]);
      }
    }
  }
  for (int e : L) {
    const bool on_slave = e < ns;
    const SurfaceMesh& body = on_slave ? slave_ : *master_;
    const std::size_t i = static_cast<std::size_t>(on_slave ? e : e - ns);
    blk.cols.push_back(body.dofs[i][0]);
    blk.cols.push_back(body.dofs[i][1]);
    if (stride() == 3) blk.cols.push_back(body.has_temperature() ? body.temperature_dofs[i] : -1);
  }
  const std::size_t nr = blk.rows.size(), nc = blk.cols.size();
  blk.r.resize(nr);
  blk.K.resize(nr * nc);
  for (std::size_t i = 0; i < nr; ++i) {
    blk.r[i] = store[i].v;
    for (std::size_t j = 0; j < nc; ++j) blk.K[i * nc + j] = store[i].d[static_cast<Eigen::Index>(j)];
  }
  return blk;
}

LawParameters ContactInterface::law_parameters(double dt) const {
  LawParameters par;
  par.cN = penalty_.cN;
  par.cT = penalty_.cT;
  par.friction = friction_.get();
  par.dt = dt;
  par.thermal = &thermal_;
  return par;
}

int ContactInterface::stride() const {
  return slave_.has_temperature() || (master_ && master_->has_temperature()) ? 3 : 2;
}

bool ContactInterface::conduction_possible() const {
  return thermal_.enabled && (master_ ? master_->has_temperature() : !std::isnan(thermal_.master_temperature));
}

/// Position of entity e as independent dual variables of stencil L.
V2<DX> ContactInterface::position_dual(const Stencil& L, int e) const {
  const int ns = slave_.num_nodes();
  const Eigen::Index S = stride() * static_cast<Eigen::Index>(L.size());
  const int b = stride() * local_index(L, e);
  const V2<double> x = e < ns ? xs_[static_cast<std::size_t>(e)] : xm_[static_cast<std::size_t>(e - ns)];
  return {variableX(x.x, b, S), variableX(x.y, b + 1, S)};
}

/// Temperature of entity e (from u) as an independent dual variable of stencil L.
DX ContactInterface::temperature_dual(const Stencil& L, int e, const double* u) const {
  const int ns = slave_.num_nodes();
  const Eigen::Index S = stride() * static_cast<Eigen::Index>(L.size());
  const int b = stride() * local_index(L, e) + 2;
  const double th = e < ns ? u[slave_.temperature_dofs[static_cast<std::size_t>(e)]]
                           : u[master_->temperature_dofs[static_cast<std::size_t>(e - ns)]];
  return variableX(th, b, S);
}

void ContactInterface::commit() {
  if (!evaluated_) throw std::logic_error("commit() before any evaluation");
  forget_evaluation();
  for (std::size_t i = 0; i < ge_.size(); ++i) ge_[i] = out_.status[i] == open ? 0.0 : out_.elastic_gap[i];
  xs_n_ = xs_;
  xm_n_ = xm_;
  offset_n_ = offset_;
  cumulative_dissipation_ += totals_.dissipation;
  ++steps_;
}

std::vector<std::pair<std::vector<DofIndex>, std::vector<DofIndex>>> ContactInterface::sparsity_blocks(
    const double* u, std::size_t n, double margin) const {
  const int ns = slave_.num_nodes();
  auto chain = [&](int A, int depth) {
    std::vector<int> nodes{A};
    int p = A, q = A;
    for (int k = 0; k < depth; ++k) {
      if (p >= 0) p = slave_.prev[static_cast<std::size_t>(p)];
      if (q >= 0) q = slave_.next[static_cast<std::size_t>(q)];
      if (p >= 0) nodes.push_back(p);
      if (q >= 0) nodes.push_back(q);
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    return nodes;
  };
  auto slave_dofs = [&](int e, std::vector<DofIndex>& out) {
    out.push_back(slave_.dofs[static_cast<std::size_t>(e)][0]);
    out.push_back(slave_.dofs[static_cast<std::size_t>(e)][1]);
    if (slave_.has_temperature()) out.push_back(slave_.temperature_dofs[static_cast<std::size_t>(e)]);
  };
  std::vector<std::pair<std::vector<DofIndex>, std::vector<DofIndex>>> blocks;
  // slave rows B receive D_AB P_A of nodes A = B-1..B+1, whose stencils reach B-3..B+3
  for (int B = 0; B < ns; ++B) {
    std::vector<DofIndex> rows, cols;
    slave_dofs(B, rows);
    for (int e : chain(B, 3)) slave_dofs(e, cols);
    blocks.emplace_back(std::move(rows), std::move(cols));
  }
  if (master_) {
    std::vector<V2<double>> xs, xm;
    positions(u, n, xs, xm);
    SegmentGrid grid;
    build_segment_grid(*master_, xm, grid);
    const double mg = margin >= 0.0 ? margin : 2.0 * search_radius();
    const double reach = mg + 1.5 * search_radius() + slave_.h_max;
    std::vector<int> ids;
    for (int A = 0; A < ns; ++A) {
      // node A couples its stencil (slave A-2..A+2, master nodes near A-1..A+1) with itself
      std::vector<DofIndex> group;
      for (int e : chain(A, 2)) slave_dofs(e, group);
      ids.clear();
      for (int e : chain(A, 1)) {
        const V2<double> x = xs[static_cast<std::size_t>(e)];
        grid.query({x.x - reach, x.y - reach}, {x.x + reach, x.y + reach}, ids);
      }
      std::set<int> mnodes;
      for (int s : ids) {
        mnodes.insert(master_->segments[static_cast<std::size_t>(s)][0]);
        mnodes.insert(master_->segments[static_cast<std::size_t>(s)][1]);
      }
      if (mnodes.empty()) continue;
      for (int m : mnodes) {
        group.push_back(master_->dofs[static_cast<std::size_t>(m)][0]);
        group.push_back(master_->dofs[static_cast<std::size_t>(m)][1]);
        if (master_->has_temperature()) group.push_back(master_->temperature_dofs[static_cast<std::size_t>(m)]);
      }
      blocks.emplace_back(group, group);
    }
  }
  return blocks;
}

std::vector<std::pair<DofIndex, DofIndex>> ContactInterface::sparsity(const double* u, std::size_t n,
                                                                      double margin) const {
  std::vector<std::pair<DofIndex, DofIndex>> pairs;
  for (const auto& [rows, cols] : sparsity_blocks(u, n, margin))
    for (DofIndex r : rows)
      for (DofIndex c : cols) pairs.emplace_back(r, c);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace rf
