#include "nodal_contact_law.hpp"

#include <cmath>

namespace rf {

NodalResponse evaluate_nodal_law(const NodalKinematics& k, double elastic_gap_old, const LawParameters& par) {
  NodalResponse r;
  const V2<DX>& n = k.normal;
  const DX gN = (k.gx * n.x + k.gy * n.y) / k.area;
  r.gap = gN.v;
  if (!(gN.v < 0.0)) return r;  // open

  const DX p = -par.cN * gN;
  r.pressure = p.v;
  r.status = stick;
  r.P = {p * n.x, p * n.y};
  DX power = constant_like(0.0, p);

  if (par.friction != nullptr) {
    const V2<DX> tau{-n.y, n.x};
    const DX dgT = (k.slip_x * tau.x + k.slip_y * tau.y) / k.area;
    const DX t_tr = par.cT * (elastic_gap_old + dgT);
    const DX v = par.dt > 0.0 ? abs(dgT) / par.dt : constant_like(0.0, p);
    const FrictionValue fv = par.friction->evaluate(p.v, v.v, k.temperature.v);
    DX mu = constant_like(fv.mu, p);
    mu.d = fv.dmu_dp * p.d + fv.dmu_dv * v.d + fv.dmu_dT * k.temperature.d;  // thesis B.8, B.9
    const DX f = abs(t_tr) - mu * p;
    DX tT = t_tr;
    r.dg_T = dgT.v;
    r.velocity = v.v;
    r.mu = fv.mu;
    if (f.v > 0.0) {  // slip: radial return (4.18)
      const double s = t_tr.v > 0.0 ? 1.0 : -1.0;
      tT = s * (mu * p);
      const DX dgamma = f / par.cT;
      r.status = slip;
      r.dgamma = dgamma.v;
      if (par.dt > 0.0) power = (mu * p) * dgamma / par.dt;
    }
    r.t_T = tT.v;
    r.elastic_gap = tT.v / par.cT;
    r.P.x += tT * tau.x;
    r.P.y += tT * tau.y;
  }
  r.friction_power = power.v;

  if (par.thermal != nullptr && par.thermal->enabled) {
    const ThermalParameters& th = *par.thermal;
    const DX hc = conductance(th, p);
    const DX gtheta = k.thermal_gap / k.area;
    r.q_slave = hc * gtheta + th.kappa * power;
    r.q_master = (1.0 - th.kappa) * power - hc * gtheta;
    r.has_heat = true;
  }
  return r;
}

}  // namespace rf
