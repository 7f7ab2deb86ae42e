// Univariate B-spline bases (value and first derivative) for tensor-product spline laws.
// Knot vectors follow the FITPACK/scipy convention: for degree k and n coefficients the knot
// vector has n + k + 1 entries and the spline lives on [t_k, t_n].
#pragma once

#include <array>
#include <vector>

namespace rf {

/// One axis of a tensor-product B-spline.
class BSplineAxis {
 public:
  BSplineAxis() = default;
  /// Validates: degree 1..5, non-decreasing knots, at least degree + 2 knots, non-empty base interval.
  BSplineAxis(std::vector<double> knots, int degree);

  int degree() const { return k_; }
  int num_coefficients() const { return static_cast<int>(t_.size()) - k_ - 1; }
  double lower() const { return t_[static_cast<std::size_t>(k_)]; }
  double upper() const { return t_[static_cast<std::size_t>(num_coefficients())]; }
  const std::vector<double>& knots() const { return t_; }

  /// Nonzero basis functions at x (clamped to [lower, upper]).
  /// Returns the index of the first nonzero function; fills value[0..k] and deriv[0..k].
  /// Outside [lower, upper] the spline is continued as a constant: derivatives are zero there.
  int evaluate(double x, std::array<double, 6>& value, std::array<double, 6>& deriv) const;

 private:
  std::vector<double> t_;
  int k_ = 3;
};

}  // namespace rf
