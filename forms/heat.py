"""Heat equation, eq. (3.89), with implicit Euler in time, eq. (5.25).

    int rho c (theta - theta_n)/dt dtheta + k grad theta . grad dtheta dV - int D dtheta dV
        + int q_hat dtheta dA = 0

Conventions: q_hat is the prescribed heat flux *out of* the body (so an inflow is negative, as in
(3.89)); D is a volumetric source (e.g. viscous dissipation, MPa/s = mW/mm^3).  Units: rho t/mm^3,
c mJ/(t K), k mW/(mm K), theta K.
"""

from __future__ import annotations

import ufl


def heat_residual(theta, theta_n, dtheta, *, rho: float, c: float, k: float, dt, source=None,
                  flux_out=None, ds=None, dx=None):
    """Residual form of eq. (3.89) with implicit Euler (5.25); linear in theta."""
    dx = dx or ufl.dx
    F = rho * c * (theta - theta_n) / dt * dtheta * dx + k * ufl.inner(ufl.grad(theta), ufl.grad(dtheta)) * dx
    if source is not None:
        F -= source * dtheta * dx
    if flux_out is not None:
        if ds is None:
            raise ValueError("flux_out needs the boundary measure ds (e.g. ds(tag))")
        F += flux_out * dtheta * ds
    return F
