#include "bspline.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rf {

BSplineAxis::BSplineAxis(std::vector<double> knots, int degree) : t_(std::move(knots)), k_(degree) {
  if (k_ < 1 || k_ > 5) {
    std::ostringstream msg;
    msg << "spline degree must be between 1 and 5, got " << k_;
    throw std::invalid_argument(msg.str());
  }
  if (t_.size() < static_cast<std::size_t>(2 * k_ + 2)) {
    std::ostringstream msg;
    msg << "spline knot vector needs at least 2*(degree+1) = " << 2 * k_ + 2 << " knots, got " << t_.size();
    throw std::invalid_argument(msg.str());
  }
  for (std::size_t i = 0; i < t_.size(); ++i) {
    if (!std::isfinite(t_[i])) throw std::invalid_argument("spline knots must be finite");
    if (i > 0 && t_[i] < t_[i - 1]) throw std::invalid_argument("spline knots must be non-decreasing");
  }
  if (!(upper() > lower())) throw std::invalid_argument("spline knot vector has an empty base interval");
}

int BSplineAxis::evaluate(double x, std::array<double, 6>& value, std::array<double, 6>& deriv) const {
  const int n = num_coefficients();
  bool outside = false;
  if (x <= lower()) {
    x = lower();
    outside = true;
  } else if (x >= upper()) {
    x = upper();
    outside = true;
  }
  // span: t[span] <= x < t[span + 1], k <= span <= n - 1
  int span = static_cast<int>(std::upper_bound(t_.begin(), t_.end(), x) - t_.begin()) - 1;
  span = std::min(std::max(span, k_), n - 1);

  // Cox-de Boor triangle (The NURBS Book, A2.2/A2.3) for degree k and k - 1.
  std::array<double, 7> left{}, right{};
  std::array<std::array<double, 7>, 7> ndu{};
  ndu[0][0] = 1.0;
  for (int j = 1; j <= k_; ++j) {
    left[static_cast<std::size_t>(j)] = x - t_[static_cast<std::size_t>(span + 1 - j)];
    right[static_cast<std::size_t>(j)] = t_[static_cast<std::size_t>(span + j)] - x;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      // lower triangle: knot differences; upper triangle: basis functions
      ndu[static_cast<std::size_t>(j)][static_cast<std::size_t>(r)] =
          right[static_cast<std::size_t>(r + 1)] + left[static_cast<std::size_t>(j - r)];
      const double temp = ndu[static_cast<std::size_t>(r)][static_cast<std::size_t>(j - 1)] /
                          ndu[static_cast<std::size_t>(j)][static_cast<std::size_t>(r)];
      ndu[static_cast<std::size_t>(r)][static_cast<std::size_t>(j)] =
          saved + right[static_cast<std::size_t>(r + 1)] * temp;
      saved = left[static_cast<std::size_t>(j - r)] * temp;
    }
    ndu[static_cast<std::size_t>(j)][static_cast<std::size_t>(j)] = saved;
  }
  for (int j = 0; j <= k_; ++j)
    value[static_cast<std::size_t>(j)] = ndu[static_cast<std::size_t>(j)][static_cast<std::size_t>(k_)];
  // first derivative: N'_{i,k} = k [N_{i,k-1}/(t_{i+k}-t_i) - N_{i+1,k-1}/(t_{i+k+1}-t_{i+1})]
  for (int r = 0; r <= k_; ++r) {
    double d = 0.0;
    if (r >= 1) {
      d += ndu[static_cast<std::size_t>(r - 1)][static_cast<std::size_t>(k_ - 1)] /
           ndu[static_cast<std::size_t>(k_)][static_cast<std::size_t>(r - 1)];
    }
    if (r <= k_ - 1) {
      d -= ndu[static_cast<std::size_t>(r)][static_cast<std::size_t>(k_ - 1)] /
           ndu[static_cast<std::size_t>(k_)][static_cast<std::size_t>(r)];
    }
    deriv[static_cast<std::size_t>(r)] = outside ? 0.0 : k_ * d;
  }
  return span - k_;
}

}  // namespace rf
