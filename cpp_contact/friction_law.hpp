// Friction coefficient laws mu(p, v, T) with their partial derivatives.
//
// p: contact pressure [MPa] (>= 0), v: sliding velocity [mm/s] (>= 0), T: temperature [K].
// The derivatives enter the consistent tangent of the return mapping (thesis B.7-B.9).
#pragma once

#include "bspline.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rf {

struct FrictionValue {
  double mu = 0.0;
  double dmu_dp = 0.0;
  double dmu_dv = 0.0;
  double dmu_dT = 0.0;
};

class FrictionLaw {
 public:
  virtual ~FrictionLaw() = default;
  virtual FrictionValue evaluate(double p, double v, double T) const = 0;
  virtual bool depends_on_velocity() const = 0;
  virtual bool depends_on_temperature() const = 0;
  virtual std::string describe() const = 0;
};

/// Coulomb friction with a constant coefficient (mu >= 0, finite).
class ConstantFriction final : public FrictionLaw {
 public:
  explicit ConstantFriction(double mu);
  FrictionValue evaluate(double, double, double) const override { return {mu_, 0.0, 0.0, 0.0}; }
  bool depends_on_velocity() const override { return false; }
  bool depends_on_temperature() const override { return false; }
  std::string describe() const override;
  double mu() const { return mu_; }

 private:
  double mu_;
};

/// Argument transform of one spline axis: the spline is a function of s = x (linear) or
/// s = log10(max(x, floor)) (log10), the usual choice for the sliding velocity over decades.
enum class AxisTransform { linear, log10 };

/// Tensor-product B-spline in (p, v) or (p, v, T) -- thesis eq. (6.6) written in the B-spline
/// basis. Coefficients are in C order (last axis fastest), the layout of scipy's
/// RectBivariateSpline tck. Outside the knot range each argument is clamped, so the law continues
/// as a constant there (zero derivative) instead of extrapolating a polynomial. The value is
/// clipped below at `mu_min` (default 0) -- with zero derivative where clipping is active.
class SplineFriction final : public FrictionLaw {
 public:
  /// axes: 2 (p, v) or 3 (p, v, T); transforms one per axis.
  SplineFriction(std::vector<BSplineAxis> axes, std::vector<double> coefficients, std::vector<AxisTransform> transforms,
                 double log_floor, double mu_min);
  FrictionValue evaluate(double p, double v, double T) const override;
  bool depends_on_velocity() const override { return true; }
  bool depends_on_temperature() const override { return axes_.size() == 3; }
  std::string describe() const override;

 private:
  std::vector<BSplineAxis> axes_;
  std::vector<double> c_;
  std::vector<AxisTransform> transforms_;
  double log_floor_;
  double mu_min_;
};

}  // namespace rf
