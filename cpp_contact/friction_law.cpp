#include "friction_law.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rf {

ConstantFriction::ConstantFriction(double mu) : mu_(mu) {
  if (!std::isfinite(mu) || mu < 0.0) {
    std::ostringstream msg;
    msg << "friction coefficient mu must be finite and >= 0, got " << mu;
    throw std::invalid_argument(msg.str());
  }
}

std::string ConstantFriction::describe() const {
  std::ostringstream s;
  s << "constant mu = " << mu_;
  return s.str();
}

SplineFriction::SplineFriction(std::vector<BSplineAxis> axes, std::vector<double> coefficients,
                               std::vector<AxisTransform> transforms, double log_floor, double mu_min)
    : axes_(std::move(axes)),
      c_(std::move(coefficients)),
      transforms_(std::move(transforms)),
      log_floor_(log_floor),
      mu_min_(mu_min) {
  if (axes_.size() != 2 && axes_.size() != 3)
    throw std::invalid_argument("SplineFriction: need 2 axes (p, v) or 3 axes (p, v, T)");
  if (transforms_.size() != axes_.size())
    throw std::invalid_argument("SplineFriction: one transform per axis is required");
  std::size_t n = 1;
  for (const auto& a : axes_) n *= static_cast<std::size_t>(a.num_coefficients());
  if (c_.size() != n) {
    std::ostringstream msg;
    msg << "SplineFriction: expected " << n << " coefficients (product of len(knots) - degree - 1 per axis), got "
        << c_.size();
    throw std::invalid_argument(msg.str());
  }
  for (double c : c_)
    if (!std::isfinite(c)) throw std::invalid_argument("SplineFriction: coefficients must be finite");
  if (!(log_floor_ > 0.0) || !std::isfinite(log_floor_))
    throw std::invalid_argument("SplineFriction: log_floor must be finite and > 0");
  if (!std::isfinite(mu_min_)) throw std::invalid_argument("SplineFriction: mu_min must be finite");
}

FrictionValue SplineFriction::evaluate(double p, double v, double T) const {
  const std::array<double, 3> x{p, v, T};
  const std::size_t dim = axes_.size();
  std::array<double, 3> s{}, ds_dx{};
  for (std::size_t a = 0; a < dim; ++a) {
    if (transforms_[a] == AxisTransform::log10) {
      const double xx = std::max(x[a], log_floor_);
      s[a] = std::log10(xx);
      ds_dx[a] = x[a] > log_floor_ ? 1.0 / (xx * std::log(10.0)) : 0.0;
    } else {
      s[a] = x[a];
      ds_dx[a] = 1.0;
    }
  }
  std::array<std::array<double, 6>, 3> b{}, db{};
  std::array<int, 3> first{}, nb{};
  std::array<int, 3> ncoef{1, 1, 1};
  for (std::size_t a = 0; a < dim; ++a) {
    first[a] = axes_[a].evaluate(s[a], b[a], db[a]);
    nb[a] = axes_[a].degree() + 1;
    ncoef[a] = axes_[a].num_coefficients();
  }
  if (dim == 2) {
    b[2][0] = 1.0;
    db[2][0] = 0.0;
    nb[2] = 1;
    first[2] = 0;
  }
  double val = 0.0;
  std::array<double, 3> grad{0.0, 0.0, 0.0};
  for (int i = 0; i < nb[0]; ++i) {
    for (int j = 0; j < nb[1]; ++j) {
      for (int k = 0; k < nb[2]; ++k) {
        const std::size_t idx = (static_cast<std::size_t>(first[0] + i) * static_cast<std::size_t>(ncoef[1]) +
                                 static_cast<std::size_t>(first[1] + j)) *
                                    static_cast<std::size_t>(ncoef[2]) +
                                static_cast<std::size_t>(first[2] + k);
        const double c = c_[idx];
        const double bi = b[0][static_cast<std::size_t>(i)], bj = b[1][static_cast<std::size_t>(j)],
                     bk = b[2][static_cast<std::size_t>(k)];
        val += c * bi * bj * bk;
        grad[0] += c * db[0][static_cast<std::size_t>(i)] * bj * bk;
        grad[1] += c * bi * db[1][static_cast<std::size_t>(j)] * bk;
        grad[2] += c * bi * bj * db[2][static_cast<std::size_t>(k)];
      }
    }
  }
  FrictionValue out;
  if (val < mu_min_) {
    out.mu = mu_min_;
    return out;
  }
  out.mu = val;
  out.dmu_dp = grad[0] * ds_dx[0];
  out.dmu_dv = grad[1] * ds_dx[1];
  out.dmu_dT = dim == 3 ? grad[2] * ds_dx[2] : 0.0;
  return out;
}

std::string SplineFriction::describe() const {
  std::ostringstream s;
  const char* names[3] = {"p", "v", "T"};
  s << "tensor-product B-spline mu(";
  for (std::size_t a = 0; a < axes_.size(); ++a) {
    if (a) s << ", ";
    s << names[a];
  }
  s << ")";
  for (std::size_t a = 0; a < axes_.size(); ++a) {
    s << "; " << names[a] << ": degree " << axes_[a].degree() << ", "
      << (transforms_[a] == AxisTransform::log10 ? "log10 axis" : "linear axis") << " on [" << axes_[a].lower() << ", "
      << axes_[a].upper() << "]";
  }
  return s.str();
}

}  // namespace rf
