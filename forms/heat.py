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
    F = (rho * c * (theta - theta_n) / dt * dtheta * dx
         + k * ufl.inner(ufl.grad(theta), ufl.grad(dtheta)) * dx)
    if source is not None:
        F -= source * dtheta * dx
    if flux_out is not None:
        if ds is None:
            raise ValueError("flux_out needs the boundary measure ds (e.g. ds(tag))")
        F += flux_out * dtheta * ds
    return F


#: Vertex quadrature (Gauss-Lobatto, 2 points per direction).  On the rectangles of the heat
#: meshes it turns the bilinear capacity into its row-sum lumped form and the conduction into the
#: five-point finite-difference stencil: an M-matrix at any aspect ratio and step, so a heat input
#: never cools a node below its surroundings (discrete maximum principle).  The consistent forms
#: break it twice: steps below h^2 / (6 alpha), and flat elements (0.25 x 0.01 mm at the contact
#: interface), whose stiffness couples neighbours along x positively.
LUMPED = {"quadrature_rule": "GLL", "quadrature_degree": 1}


def convected_heat_forms(theta, dtheta, theta_n, *, rho_c, k, dt, velocity=None, tau=None, dx=None,
                         lumped: bool = False):
    """Bilinear and linear forms of the linear heat equation (3.89) with implicit Euler (5.25) in
    a frame where the material moves with `velocity` (Eulerian road under a sliding block):

        a = int rho c/dt theta s + k grad theta . grad s + rho c (b . grad theta) s dV
            + int tau (b . grad s) rho c (theta/dt + b . grad theta) dV        (SUPG)
        L = int rho c/dt theta_n s + tau (b . grad s) rho c theta_n/dt dV

    rho_c, k, tau may be cellwise (DG0) coefficients; dt = None drops the time terms (steady
    state).  The SUPG term uses the strong residual without the diffusion part, which vanishes
    for bilinear elements on rectangles (Delta theta = 0), so the scheme stays consistent; its
    test function b . grad s integrates to zero over the body, so the heat balance is unchanged.
    L is None in the steady case.  ``lumped`` integrates the Galerkin capacity and conduction
    terms at the vertices (:data:`LUMPED`; convection and SUPG stay Gauss), which keeps implicit
    Euler free of under- and overshoots at any step and aspect ratio.
    """
    dx = dx or ufl.dx
    dx_c = dx(metadata=LUMPED) if lumped else dx
    a = k * ufl.inner(ufl.grad(theta), ufl.grad(dtheta)) * dx_c
    L = None
    if dt is not None:
        a += rho_c / dt * theta * dtheta * dx_c
        L = rho_c / dt * theta_n * dtheta * dx_c
    if velocity is not None:
        b_grad = ufl.dot(velocity, ufl.grad(theta))
        a += rho_c * b_grad * dtheta * dx
        if tau is not None:
            test = tau * ufl.dot(velocity, ufl.grad(dtheta))
            a += test * rho_c * b_grad * dx
            if dt is not None:
                a += test * rho_c / dt * theta * dx
                L += test * rho_c / dt * theta_n * dx
    return a, L
