#include "thermal_contact.hpp"

#include <sstream>
#include <stdexcept>

namespace rf {

void ThermalParameters::validate() const {
  auto bad = [](const char* field, double value, const char* expected) {
    std::ostringstream m;
    m << "thermal contact: " << field << " = " << value << " is invalid, expected " << expected;
    throw std::invalid_argument(m.str());
  };
  if (!std::isfinite(h0) || h0 < 0.0) bad("h0", h0, "a finite conductance >= 0");
  if (!std::isfinite(h1) || h1 < 0.0) bad("h1", h1, "a finite coefficient >= 0");
  if (!std::isfinite(beta) || beta < 1.0) bad("beta", beta, "a finite exponent >= 1");
  if (!std::isfinite(kappa) || kappa < 0.0 || kappa > 1.0) bad("kappa", kappa, "a heat share in [0, 1]");
  if (std::isinf(master_temperature) || master_temperature <= 0.0)
    bad("master_temperature", master_temperature, "NaN (none) or a temperature > 0 K");
}

std::string ThermalParameters::describe() const {
  std::ostringstream s;
  s << "h_c(p) = " << h0 << " + " << h1 << " p^" << beta << " mW/(mm^2 K), kappa = " << kappa;
  if (!std::isnan(master_temperature)) s << ", rigid master at " << master_temperature << " K";
  return s.str();
}

DX conductance(const ThermalParameters& t, const DX& p) {
  DX h = constant_like(t.h0, p);
  if (t.h1 != 0.0) h += t.h1 * pow(p, t.beta);
  return h;
}

}  // namespace rf
