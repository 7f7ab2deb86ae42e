// Forward-mode automatic differentiation for the contact kernels.
//
// A Dual carries a value and its gradient with respect to a *local* set of variables: the 12
// coordinates of one slave-segment / master-segment pair (fixed size, no allocation) or the
// coordinates and temperatures of the stencil of one slave node (dynamic size). Every quantity of
// the contact residual is computed with Duals, so the Jacobian is the exact derivative of the
// residual, including the projections, the segmentation points and the averaged normals.
// Discrete decisions (active set, stick/slip, pairing) are taken on values and held fixed.
#pragma once

#include <Eigen/Core>

#include <cmath>

namespace rf {

/// Gradient of a default-constructed Dual: zero for a fixed size; empty (size 0) for a dynamic
/// size, which is unknown until the first assignment (a default DX must be assigned before use).
template <class Grad>
Grad zero_gradient() {
  if constexpr (Grad::SizeAtCompileTime == Eigen::Dynamic)
    return Grad();
  else
    return Grad::Zero();
}

template <class Grad>
struct Dual {
  double v = 0.0;                  ///< value
  Grad d = zero_gradient<Grad>();  ///< gradient with respect to the local variables

  Dual() = default;
  Dual(double value, const Grad& grad) : v(value), d(grad) {}
  template <class Expr>
  Dual(double value, const Eigen::MatrixBase<Expr>& grad) : v(value), d(grad) {}

  Dual& operator+=(const Dual& o) {
    v += o.v;
    d += o.d;
    return *this;
  }
  Dual& operator-=(const Dual& o) {
    v -= o.v;
    d -= o.d;
    return *this;
  }
  Dual& operator*=(double s) {
    v *= s;
    d *= s;
    return *this;
  }
};

using Grad12 = Eigen::Matrix<double, 12, 1>;
using D12 = Dual<Grad12>;          ///< segment-pair kernels: 6 nodes x 2 coordinates
using DX = Dual<Eigen::VectorXd>;  ///< nodal laws: dynamic stencil

/// A constant (zero gradient) of the same gradient size as `like`.
template <class G>
inline Dual<G> constant_like(double value, const Dual<G>& like) {
  return Dual<G>(value, G::Zero(like.d.size()));
}
inline D12 constant12(double value) { return D12(value, Grad12::Zero()); }
inline DX constantX(double value, Eigen::Index n) { return DX(value, Eigen::VectorXd::Zero(n)); }
/// The independent variable number `i` of `n`, with value `value`.
inline DX variableX(double value, Eigen::Index i, Eigen::Index n) {
  DX r = constantX(value, n);
  r.d[i] = 1.0;
  return r;
}
inline D12 variable12(double value, int i) {
  D12 r = constant12(value);
  r.d[i] = 1.0;
  return r;
}

inline double value_of(double x) { return x; }
template <class G>
inline double value_of(const Dual<G>& x) {
  return x.v;
}

template <class G>
inline Dual<G> operator+(const Dual<G>& a, const Dual<G>& b) {
  return Dual<G>(a.v + b.v, a.d + b.d);
}
template <class G>
inline Dual<G> operator-(const Dual<G>& a, const Dual<G>& b) {
  return Dual<G>(a.v - b.v, a.d - b.d);
}
template <class G>
inline Dual<G> operator-(const Dual<G>& a) {
  return Dual<G>(-a.v, -a.d);
}
template <class G>
inline Dual<G> operator*(const Dual<G>& a, const Dual<G>& b) {
  return Dual<G>(a.v * b.v, b.v * a.d + a.v * b.d);
}
template <class G>
inline Dual<G> operator/(const Dual<G>& a, const Dual<G>& b) {
  const double inv = 1.0 / b.v;
  const double q = a.v * inv;
  return Dual<G>(q, (a.d - q * b.d) * inv);
}
template <class G>
inline Dual<G> operator+(const Dual<G>& a, double s) {
  return Dual<G>(a.v + s, a.d);
}
template <class G>
inline Dual<G> operator+(double s, const Dual<G>& a) {
  return Dual<G>(a.v + s, a.d);
}
template <class G>
inline Dual<G> operator-(const Dual<G>& a, double s) {
  return Dual<G>(a.v - s, a.d);
}
template <class G>
inline Dual<G> operator-(double s, const Dual<G>& a) {
  return Dual<G>(s - a.v, -a.d);
}
template <class G>
inline Dual<G> operator*(const Dual<G>& a, double s) {
  return Dual<G>(a.v * s, a.d * s);
}
template <class G>
inline Dual<G> operator*(double s, const Dual<G>& a) {
  return Dual<G>(a.v * s, a.d * s);
}
template <class G>
inline Dual<G> operator/(const Dual<G>& a, double s) {
  return Dual<G>(a.v / s, a.d / s);
}
template <class G>
inline Dual<G> operator/(double s, const Dual<G>& a) {
  const double q = s / a.v;
  return Dual<G>(q, (-q / a.v) * a.d);
}

template <class G>
inline Dual<G> sqrt(const Dual<G>& a) {
  const double r = std::sqrt(a.v);
  return Dual<G>(r, r > 0.0 ? ((0.5 / r) * a.d).eval() : (0.0 * a.d).eval());
}
/// |a| with the derivative sign(a) (0 at a = 0).
template <class G>
inline Dual<G> abs(const Dual<G>& a) {
  const double s = a.v > 0.0 ? 1.0 : (a.v < 0.0 ? -1.0 : 0.0);
  return Dual<G>(std::abs(a.v), s * a.d);
}
/// a^e for a > 0 (and a = 0 when e >= 1).
template <class G>
inline Dual<G> pow(const Dual<G>& a, double e) {
  const double r = std::pow(a.v, e);
  const double dr = (a.v == 0.0) ? (e == 1.0 ? 1.0 : 0.0) : e * std::pow(a.v, e - 1.0);
  return Dual<G>(r, dr * a.d);
}

}  // namespace rf
