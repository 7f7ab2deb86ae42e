// Mortar segment-to-segment integration for linear 2D segments (thesis eqs. 5.33-5.38), and the
// node-to-segment collocation variant, computed with dual numbers over the 12 coordinates
//   slot 0: prev(a)   slot 1: a   slot 2: b   slot 3: next(b)   (slave segment and its stencil)
//   slot 4: master node c   slot 5: master node d             (master segment c -> d)
// so that every integral carries its exact derivative with respect to those coordinates.
//
// Kinematics (5.36): the nodal slave normal n_A is the normal of the averaged base vector,
// n_A = right_normal(x_next - x_prev)/|.| (x_A replaces a missing neighbour at a chain end). Inside
// a slave segment the normal field is n(xi) = (1 - xi) n_a + xi n_b, with the master's normal at a
// vertex end (SlaveSegment::vertex_a). Master nodes are projected
// onto the slave segment along n(xi); a slave point x1(xi) is projected onto the master segment
// along n(xi). The overlap of the two projections is the integration segment; Gauss points live
// on the slave segment (da = |x_b - x_a| dxi). Integrals per segment piece:
//   gap[A]  = Int M_A (x2 - x1) da          (vector weighted gap, 5.38)
//   area[A] = Int M_A da                    (nodal mortar weight)
//   D[A][B] = Int M_A N_B da,  M[A][C] = Int M_A N_C(eta) da
//   nu[A]   = Int M_A nu2 da,  nu2 = -(outward master normal): the master's normal seen from
//             the slave, the contact frame of a slave chain end (contact_interface.cpp, phase 4)
// with M_A = N_A the standard linear Lagrange-multiplier shape functions (5.35).
#pragma once

#include "dual.hpp"
#include "vec2.hpp"

#include <array>

namespace rf {

/// Current positions of one slave segment (a, b) and its neighbours.
struct SlaveSegment {
  std::array<V2<double>, 4> x;  ///< prev(a), a, b, next(b); prev/next equal a/b when absent
  bool has_prev = false, has_next = false;
  /// a (b) is a vertex end (ContactInterface::vertex_end) against a rigid master: n(xi) takes
  /// there the master's normal nu2 = -(outward master normal), the vertex's contact frame, not the
  /// one-sided normal of the segment, which turns with the segment as a loaded corner tilts it
  /// (past 90 degrees it faces away from the master, and the points next to the vertex lost
  /// their pairing).  Per piece nu2 is its own master segment's, a constant of a rigid master;
  /// a deformable master keeps the one-sided normal (nu2 of a neighbouring master segment
  /// would depend on nodes outside the piece's slots)
  bool vertex_a = false, vertex_b = false;
};

/// Current positions of a master segment c -> d and the sign of its outward normal
/// (+1: right normal = deformable body rule, -1: left normal = rigid polyline rule).
struct MasterSegment {
  V2<double> q0, q1;
  double normal_sign = 1.0;
  V2<double> outward_normal() const {
    const V2<double> n = normalized(right_normal(q1 - q0));
    return normal_sign * n;
  }
  /// The same over dual coordinates (q0 -> q1 given as duals).
  template <class T>
  V2<T> outward_normal(const V2<T>& d0, const V2<T>& d1) const {
    return normal_sign * normalized(right_normal(d1 - d0));
  }
};

/// Where an end point of an integration piece comes from.
struct Breakpoint {
  enum Kind { slave_start, slave_end, master_q0, master_q1, foreign };
  Kind kind = slave_start;
  double xi = 0.0;         ///< value
  V2<double> q{0.0, 0.0};  ///< master node for `foreign` (constant coordinates)
  /// Taken from another master segment's overlap on a slave segment with a vertex end: the
  /// vertex projected along that segment's normal `vertex_normal` (a constant: rigid master)
  bool other_normal = false;
  V2<double> vertex_normal{0.0, 0.0};
};

/// Integrals of one slave segment against one master segment piece (or, for node-to-segment,
/// of one slave node: index 0 only).
struct PairIntegrals {
  std::array<std::array<D12, 2>, 2> gap;  ///< [A][component]
  std::array<D12, 2> area;
  std::array<std::array<D12, 2>, 2> D;  ///< [A][B]
  std::array<std::array<D12, 2>, 2> M;  ///< [A][C]
  std::array<V2<D12>, 2> nu;            ///< [A] Int M_A nu2 da, nu2 = -(outward master normal)
  void set_zero();
};

/// Nodal normals n_a, n_b of a slave segment (values only); a vertex end (vertex_a, vertex_b)
/// takes the normal nu2 = -(outward normal) of master segment m.
void nodal_normals(const SlaveSegment& s, const MasterSegment& m, V2<double>& na, V2<double>& nb);
/// The averaged (one-sided at a chain end) slave normals alone, values only.
void nodal_normals(const SlaveSegment& s, V2<double>& na, V2<double>& nb);

/// Overlap of master segment m with slave segment s in slave coordinates: the slave ends are
/// projected along their nodal normals onto the master line; master nodes lying between them are
/// projected onto the slave segment along n(xi).
struct Overlap {
  bool valid = false;
  double lo = 0.0, hi = 0.0;
  Breakpoint::Kind lo_kind = Breakpoint::slave_start, hi_kind = Breakpoint::slave_end;
};
Overlap overlap(const SlaveSegment& s, const V2<double>& na, const V2<double>& nb, const MasterSegment& m);

/// Normal gap (x2 - x1) . n(xi)/|n(xi)| at slave coordinate xi (the master segment line is used).
double normal_gap_at(const SlaveSegment& s, const V2<double>& na, const V2<double>& nb, const MasterSegment& m,
                     double xi);

/// Gauss integration of the mortar integrals over the piece [lo, hi] of slave segment s paired
/// with master segment m. Adds into `out`.
void integrate_piece(const SlaveSegment& s, const MasterSegment& m, const Breakpoint& lo, const Breakpoint& hi,
                     int n_gauss, PairIntegrals& out);

/// Node-to-segment collocation at slave node A (slots: 0 prev, 1 A, 2 next, 4/5 master):
/// the node is projected along its averaged normal onto the master segment; weight = half the
/// adjacent slave segment lengths. Fills index A = 0 of `out` (D[0][0] is the lumped weight; nu[0]
/// the weight times the master's normal seen from the slave).
/// Returns false if the projection does not fall on the segment.
bool node_to_segment(const std::array<V2<double>, 3>& x, bool has_prev, bool has_next, const MasterSegment& m,
                     PairIntegrals& out, double& eta, double& gap);

/// Orders (points per integration piece) of the Gauss-Legendre table.
constexpr int kMinGaussPoints = 1, kMaxGaussPoints = 8;

/// Gauss-Legendre rule on [-1, 1]: points x[0..n) in descending order and their weights.
struct GaussRule {
  int n = 0;
  std::array<double, kMaxGaussPoints> x{}, w{};
};

/// The rule with n points from a constant table; std::invalid_argument outside
/// [kMinGaussPoints, kMaxGaussPoints].
const GaussRule& gauss_legendre(int n);

}  // namespace rf
