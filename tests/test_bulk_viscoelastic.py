"""Finite linear viscoelasticity (eqs. 3.72-3.78) against the linear closed forms.

Homogeneous shear of amplitude 1e-5 on one element: the finite-strain model equals linear
viscoelasticity up to O(gamma^2) ~ 1e-10, so the closed forms of the Prony series (eq. 3.34,
G(t) = G_inf (1 + sum g_k exp(-t/tau_k)) with the Mooney-Rivlin constants as long-term moduli)
are exact references.
"""

import numpy as np
import pytest

from fe_helpers import cauchy_at_points, n_full, unit_square
from rubberfriction.driver.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.newton import ConstrainedNonlinearProblem, NewtonSettings, NewtonSolver
from rubberfriction.driver.solid import SolidProblem
from rubberfriction.forms.materials import Compound, MooneyRivlin, PronySeries

C10, C01, D1 = 0.174, 0.300, 0.0208
G_INF = 2.0 * (C10 + C01)
GAMMA0 = 1e-5


def compound(gamma, tau) -> Compound:
    return Compound(name="visco-test", hyperelastic=MooneyRivlin(C10, C01, D1),
                    prony=PronySeries(np.asarray(gamma), np.asarray(tau)), wlf=None, thermal=None,
                    description="test", source="synthetic")


class ShearDriver:
    """One element in homogeneous simple shear gamma(t) with every node prescribed."""

    def __init__(self, gamma, tau):
        m, ft = unit_square(1)
        self.sp = SolidProblem(m, ft, compound(gamma, tau))
        spec = ConstraintSpec(n_full(self.sp))
        d = self.sp.displacement_dofs()
        spec.fix(d.ravel(), 0.0)
        self.cmap = ConstraintMap(spec)
        self.ux_dofs, self.z = d[:, 0], self.sp.node_X[:, 1]
        self.pb = ConstrainedNonlinearProblem(self.sp.residual, self.sp.jacobian(), self.sp.w, self.cmap)
        self.newton = NewtonSolver(self.pb, NewtonSettings(rtol=1e-12, atol=1e-15))

    def step(self, gamma: float, dt: float) -> tuple[float, float]:
        """Advance one step; returns (shear stress, viscous energy of the step)."""
        for dof, z in zip(self.ux_dofs, self.z):
            self.cmap.fixed_roots[int(self.cmap.roots[dof])] = gamma * z
        self.sp.prepare_step(dt)
        res = self.newton.solve()
        assert res.converged, res.reason
        dE = self.sp.commit_step()
        return float(cauchy_at_points(self.sp)[:, 0, 1].mean()), dE


def ramp_hold_error(dt: float, t_ramp: float, gamma, tau, t_end: float) -> float:
    """Max relative error of the stress over a ramp-and-hold history sampled every dt."""
    g = np.asarray(gamma) / (1.0 - np.sum(gamma))
    tau = np.asarray(tau)
    drv = ShearDriver(gamma, tau)
    n = int(round(t_end / dt))
    errs = []
    for i in range(1, n + 1):
        t = i * dt
        s, _ = drv.step(GAMMA0 * min(t / t_ramp, 1.0), dt)
        if t >= t_ramp - 1e-12:
            # sigma(t) = gamma0 G_inf [1 + sum g_k tau_k e^{-t/tau_k} (e^{t_r/tau_k} - 1) / t_r]
            exact = GAMMA0 * G_INF * (1.0 + np.sum(g * tau * np.exp(-t / tau) * np.expm1(t_ramp / tau)) / t_ramp)
            errs.append(abs(s - exact) / exact)
    return max(errs)


GAMMA_K, TAU_K = [0.5, 0.3], [0.01, 0.1]


def test_relaxation_within_one_percent_and_second_order():
    """Ramp over tau_min/10 then hold: within 1 % at all times; error falls as dt^2."""
    t_ramp = TAU_K[0] / 10.0
    e1 = ramp_hold_error(t_ramp, t_ramp, GAMMA_K, TAU_K, t_end=0.3)
    e2 = ramp_hold_error(t_ramp / 2.0, t_ramp, GAMMA_K, TAU_K, t_end=0.3)
    assert e1 < 0.01, e1
    order = np.log2(e1 / e2)
    assert 1.8 < order < 2.2, (e1, e2, order)


@pytest.mark.parametrize("omega_tau", [0.1, 1.0, 10.0])
def test_harmonic_shear_storage_loss_and_dissipation(omega_tau):
    """gamma = gamma0 sin(omega t) across the loss peak of one Maxwell term.

    G', G'' from a least-squares fit of the FE stress (sin, cos and the known transient
    exp(-t/tau)) match eq. (3.34) (shear form, E = 3G when incompressible) within 1 %, and the
    viscous energy per cycle equals pi gamma0^2 G'' within 1 %.
    """
    gamma_k, tau = 0.6, 0.05
    omega = omega_tau / tau
    g = gamma_k / (1.0 - gamma_k)
    Gs = G_INF * (1.0 + g * (omega * tau) ** 2 / (1.0 + (omega * tau) ** 2))
    Gl = G_INF * g * omega * tau / (1.0 + (omega * tau) ** 2)
    drv = ShearDriver([gamma_k], [tau])
    per_cycle, cycles = 200, 6
    dt = 2.0 * np.pi / omega / per_cycle
    t = dt * np.arange(1, per_cycle * cycles + 1)
    stress, energy = np.empty_like(t), np.empty_like(t)
    for i, ti in enumerate(t):
        stress[i], energy[i] = drv.step(GAMMA0 * np.sin(omega * ti), dt)
    A = np.column_stack([np.sin(omega * t), np.cos(omega * t), np.exp(-t / tau)])
    coef = np.linalg.lstsq(A, stress, rcond=None)[0]
    assert abs(coef[0] / GAMMA0 - Gs) < 0.01 * Gs
    assert abs(coef[1] / GAMMA0 - Gl) < 0.01 * Gl
    last = slice(-per_cycle, None)
    W_cycle = energy[last].sum()  # unit square, depth 1
    assert abs(W_cycle - np.pi * GAMMA0**2 * Gl) < 0.01 * np.pi * GAMMA0**2 * Gl
    # loop area of the FE stress-strain curve over the last cycle (trapezoid) agrees too
    gam = GAMMA0 * np.sin(omega * t[-per_cycle - 1:])
    sig = stress[-per_cycle - 1:]
    loop = np.sum(0.5 * (sig[1:] + sig[:-1]) * np.diff(gam))
    assert abs(loop - np.pi * GAMMA0**2 * Gl) < 0.01 * np.pi * GAMMA0**2 * Gl
