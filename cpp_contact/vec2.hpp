// A 2D vector over a scalar type T (double or Dual), with the few operations the contact
// kinematics needs. Plane x-z of the project, stored as (x, y).
#pragma once

#include "dual.hpp"

#include <Eigen/Core>

#include <cmath>

namespace rf {

template <class T>
struct V2 {
  T x, y;
};

template <class T>
inline V2<T> operator+(const V2<T>& a, const V2<T>& b) {
  return {a.x + b.x, a.y + b.y};
}
template <class T>
inline V2<T> operator-(const V2<T>& a, const V2<T>& b) {
  return {a.x - b.x, a.y - b.y};
}
template <class T, class S>
inline V2<T> operator*(const S& s, const V2<T>& a) {
  return {s * a.x, s * a.y};
}
template <class T>
inline T dot(const V2<T>& a, const V2<T>& b) {
  return a.x * b.x + a.y * b.y;
}
/// z-component of the 3D cross product of (a, 0) and (b, 0).
template <class T>
inline T cross(const V2<T>& a, const V2<T>& b) {
  return a.x * b.y - a.y * b.x;
}
template <class T>
inline T norm(const V2<T>& a) {
  using std::sqrt;
  return sqrt(a.x * a.x + a.y * a.y);
}
/// Tangent rotated clockwise by 90 degrees: the outward normal of a boundary traversed
/// counter-clockwise around its body (body on the left of the tangent).
template <class T>
inline V2<T> right_normal(const V2<T>& t) {
  return {t.y, -t.x};
}
/// Tangent rotated counter-clockwise by 90 degrees (body on the right of the tangent).
template <class T>
inline V2<T> left_normal(const V2<T>& t) {
  return {-t.y, t.x};
}
template <class T>
inline V2<T> normalized(const V2<T>& a) {
  const T n = norm(a);
  return {a.x / n, a.y / n};
}

inline V2<double> values(const V2<double>& a) { return a; }
template <class G>
inline V2<double> values(const V2<Dual<G>>& a) {
  return {a.x.v, a.y.v};
}

inline V2<double> from_eigen(const Eigen::Vector2d& v) { return {v.x(), v.y()}; }
inline Eigen::Vector2d to_eigen(const V2<double>& v) { return {v.x, v.y}; }

/// Lift a double vector to constant Duals of gradient size like `like`.
template <class G>
inline V2<Dual<G>> lift(const V2<double>& a, const Dual<G>& like) {
  return {constant_like(a.x, like), constant_like(a.y, like)};
}

}  // namespace rf
