// Thermal contact parameters (thesis eqs. 4.24-4.26, 5.44, 5.45).
//
// Heat flux density into the slave across the interface: q_c = h_c(p) (theta_2 - theta_1), with
// h_c(p) = h0 + h1 p^beta [mW/(mm^2 K)], p in MPa, beta >= 1. Conductance acts where the node is in
// contact (p > 0). Frictional heating: the dissipated power density w = |t_T| dgamma/dt (zero in
// stick) goes a fraction kappa to the slave and 1 - kappa to the master.
#pragma once

#include "dual.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace rf {

struct ThermalParameters {
  bool enabled = false;
  double h0 = 0.0;     ///< conductance at zero pressure [mW/(mm^2 K)]
  double h1 = 0.0;     ///< pressure coefficient [mW/(mm^2 K MPa^beta)]
  double beta = 1.0;   ///< pressure exponent (>= 1)
  double kappa = 0.5;  ///< share of the frictional heat going to the slave, in [0, 1]
  /// Temperature of a rigid master [K] (NaN: the rigid master takes no part in conduction).
  double master_temperature = std::numeric_limits<double>::quiet_NaN();

  void validate() const;
  std::string describe() const;
};

/// h_c(p) = h0 + h1 p^beta.
DX conductance(const ThermalParameters& t, const DX& p);

}  // namespace rf
