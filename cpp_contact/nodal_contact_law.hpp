// Nodal contact law: penalty normal traction (5.39), tangential penalty with Coulomb return
// mapping (4.17), (4.18), (5.40) and a friction coefficient mu(p, v, T) whose derivatives enter
// the tangent (B.7-B.9), and the thermal interface fluxes (4.26), (5.44), (5.45).
//
// All inputs are dual numbers over the stencil of the slave node, so the response carries its
// exact derivatives. Conventions (per slave node A, weight A_A = Int M_A da):
//   normal gap        g_A  = (gbar_A . n_A) / A_A            >= 0 open
//   pressure          p_A  = c_N <-g_A>                       >= 0
//   slip increment    dg_A = (dgbar_A . tau_A) / A_A, tau_A = (-n_y, n_x), the nodal tangent
//                     (n_A: the averaged slave normal, at a chain end the master's, see
//                     ContactInterface::nodal_kinematics)
//   trial traction    t_tr = c_T (g_e^n + dg_A),  f = |t_tr| - mu p
//   stick (f <= 0)    t_T = t_tr;   slip: t_T = mu p sign(t_tr), dgamma = f / c_T
//   penalty vector    P_A  = p_A n_A + t_T tau_A   (the slave receives -P_A per unit area)
//   sliding velocity  v_A = |dg_A| / dt  (relative slave-master velocity of the step)
#pragma once

#include "dual.hpp"
#include "friction_law.hpp"
#include "thermal_contact.hpp"
#include "vec2.hpp"

namespace rf {

struct NodalKinematics {
  DX gx, gy;          ///< weighted gap vector Int M_A (x2 - x1) da
  DX area;            ///< nodal weight A_A
  V2<DX> normal;      ///< nodal frame n_A (averaged slave normal; master's at chain ends)
  DX slip_x, slip_y;  ///< weighted relative displacement increment of the step
  DX temperature;     ///< temperature used in mu(p, v, T)
  DX thermal_gap;     ///< weighted thermal gap Int M_A (theta_2 - theta_1) da
};

struct LawParameters {
  double cN = 0.0, cT = 0.0;
  const FrictionLaw* friction = nullptr;  ///< null: frictionless
  double dt = 0.0;
  const ThermalParameters* thermal = nullptr;  ///< null or disabled: no thermal terms
};

enum ContactStatus : int { open = 0, stick = 1, slip = 2 };

struct NodalResponse {
  int status = open;
  V2<DX> P;              ///< penalty force density vector (valid if status != open)
  DX q_slave, q_master;  ///< heat flux densities into slave / master [mW/mm^2]
  double gap = 0.0, pressure = 0.0, t_T = 0.0, dgamma = 0.0, dg_T = 0.0, velocity = 0.0, mu = 0.0;
  double elastic_gap = 0.0;     ///< tangential elastic gap to commit
  double friction_power = 0.0;  ///< dissipated power density w [mW/mm^2]
  bool has_heat = false;
};

NodalResponse evaluate_nodal_law(const NodalKinematics& k, double elastic_gap_old, const LawParameters& par);

}  // namespace rf
