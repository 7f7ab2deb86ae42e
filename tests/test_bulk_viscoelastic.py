"""Finite linear viscoelasticity (eqs. 3.72-3.78) against the linear closed forms.

Calls the same code as ``rubberfriction verify relaxation``.  Homogeneous shear of amplitude 1e-5:
the finite-strain model equals linear viscoelasticity up to O(gamma^2) ~ 1e-10.  Two history
schemes: the thesis' midpoint rule (3.76) and the default one exact for Sbar linear in time.

The closed forms are evaluated here.  Long-term shear modulus G_inf = 2 (C10 + C01) (eq. A.8),
relative Prony moduli g_k = gamma_k / (1 - sum gamma):

* ramp to gamma0 over t_ramp, then hold (t >= t_ramp):
  tau_xy(t) = gamma0 G_inf [1 + sum_k g_k tau_k e^(-t/tau_k) (e^(t_ramp/tau_k) - 1) / t_ramp];
* harmonic shear gamma0 sin(omega t) (eq. 3.34 in shear form):
  G' = G_inf [1 + sum_k g_k (omega tau_k)^2 / (1 + (omega tau_k)^2)],
  G'' = G_inf sum_k g_k omega tau_k / (1 + (omega tau_k)^2),  energy per cycle pi gamma0^2 G''.
"""

import numpy as np
import pytest

from rubberfriction.driver.verification.relaxation import (
    finite_harmonic_shear,
    finite_shear_cycle_energy,
    harmonic_shear,
    ramp_hold,
)
from rubberfriction.forms.compound import MooneyRivlin

C10, C01, D1 = 0.174, 0.300, 0.0208  # compound m1, table C.2
M1 = MooneyRivlin(C10, C01, D1)
GAMMA_K, TAU_K = [0.5, 0.3], [0.01, 0.1]
GAMMA0 = 1e-5
G_INF = 2.0 * (C10 + C01)


def relative_moduli(gamma):
    gamma = np.asarray(gamma, float)
    return gamma / (1.0 - gamma.sum())


def ramp_hold_exact(t, t_ramp, gamma, tau):
    g, tau = relative_moduli(gamma), np.asarray(tau, float)
    t = np.asarray(t, float)[:, None]
    return GAMMA0 * G_INF * (1.0 + np.sum(g * tau * np.exp(-t / tau) * np.expm1(t_ramp / tau),
                                          axis=1) / t_ramp)


def harmonic_exact(omega, gamma, tau):
    g, wt = relative_moduli(gamma), omega * np.asarray(tau, float)
    G1 = G_INF * (1.0 + np.sum(g * wt**2 / (1.0 + wt**2)))
    G2 = G_INF * np.sum(g * wt / (1.0 + wt**2))
    return G1, G2, np.pi * GAMMA0**2 * G2


def ramp_hold_error(dt, t_ramp, scheme):
    r = ramp_hold(M1, GAMMA_K, TAU_K, dt=dt, t_ramp=t_ramp, t_end=0.3, gamma0=GAMMA0, scheme=scheme)
    t, stress = np.asarray(r["t"]), np.asarray(r["stress"])
    assert t.size >= 0.3 / dt - 1 and t.min() >= t_ramp - 1e-12  # every sample of the hold
    return float(np.max(np.abs(stress / ramp_hold_exact(t, t_ramp, GAMMA_K, TAU_K) - 1.0)))


def test_relaxation_midpoint_within_one_percent_and_second_order():
    """Midpoint rule: ramp over tau_min/10 then hold is within 1 % at all times; error ~ dt^2."""
    t_ramp = TAU_K[0] / 10.0
    e1 = ramp_hold_error(t_ramp, t_ramp, "midpoint")
    e2 = ramp_hold_error(t_ramp / 2.0, t_ramp, "midpoint")
    assert e1 < 0.01, e1
    order = np.log2(e1 / e2)
    assert 1.8 < order < 2.2, order


def test_relaxation_linear_scheme_exact_for_ramps():
    """The default scheme integrates a linear-in-time strain exactly: round-off only, any dt/tau."""
    for dt in (TAU_K[0] / 10.0, 3.0 * TAU_K[0]):
        e = ramp_hold_error(dt, dt, "linear")
        assert e < 1e-7, (dt, e)


@pytest.mark.parametrize("scheme", ["linear", "midpoint"])
def test_harmonic_shear_second_order(scheme):
    """Smooth input: both schemes converge at second order in dt (G'' at omega tau = 1)."""
    tau = 0.05
    _, G2, _ = harmonic_exact(1.0 / tau, [0.6], [tau])
    err = []
    for per_cycle in (16, 32):
        h = harmonic_shear(M1, [0.6], [tau], omega=1.0 / tau, per_cycle=per_cycle, cycles=6,
                           gamma0=GAMMA0, scheme=scheme)
        err.append(abs(h["G_loss"] - G2) / G2)
    order = np.log2(err[0] / err[1])
    assert 1.7 < order < 2.3, (err, order)


@pytest.mark.parametrize("omega_tau", [0.1, 1.0, 10.0])
def test_harmonic_shear_storage_loss_and_dissipation(omega_tau):
    """G', G'' within 1 % of eq. (3.34); energy per cycle and loop area = pi gamma0^2 G'' within
    1 %."""
    tau = 0.05
    G1, G2, energy = harmonic_exact(omega_tau / tau, [0.6], [tau])
    h = harmonic_shear(M1, [0.6], [tau], omega=omega_tau / tau, gamma0=GAMMA0)
    assert abs(h["G_storage"] - G1) < 0.01 * G1, (h["G_storage"], G1)
    assert abs(h["G_loss"] - G2) < 0.01 * G2, (h["G_loss"], G2)
    assert abs(h["energy_per_cycle"] - energy) < 0.01 * energy
    assert abs(h["loop_area"] - energy) < 0.01 * energy


# --- energy balance at finite strain (thesis eq. 2.8 needs the model's own dissipation) ---------
def finite_shear_cycle_work_ode(gamma0: float, omega: float, g: float, tau: float) -> float:
    """Oracle: work per cycle and unit volume of the one-term model in simple shear
    gamma0 sin(omega t) at finite strain, from the branch ODE integrated by scipy.

    J = 1 and Cbar = C = [[1, gamma, 0], [gamma, 1 + gamma^2, 0], [0, 0, 1]]; the equilibrium
    stress is conservative, so the cycle work is that of the branch: g/2 oint H : dC/dt dt, with
    H' = -H/tau + d DEV{Sbar}/dt, DEV{Sbar} = Sbar - (Sbar : C)/3 C^-1 and Sbar = 2 [(C10 +
    C01 tr C) 1 - C01 C] (Mooney-Rivlin).  Written for K = H - DEV{Sbar}: K' = -(K + DEV{Sbar})
    / tau.  Integrated from rest over 8 periods (omega tau = 1: the start is forgotten to
    exp(-14 pi)), the work of the last one."""
    from scipy.integrate import solve_ivp

    def sdev(t):
        gam = gamma0 * np.sin(omega * t)
        C = np.array([[1.0, gam, 0.0], [gam, 1.0 + gam**2, 0.0], [0.0, 0.0, 1.0]])
        Sbar = 2.0 * ((C10 + C01 * np.trace(C)) * np.eye(3) - C01 * C)
        return Sbar - np.tensordot(Sbar, C) / 3.0 * np.linalg.inv(C), gam

    def rhs(t, y):
        S, gam = sdev(t)
        H = y[:9].reshape(3, 3) + S
        dgam = gamma0 * omega * np.cos(omega * t)
        power = 0.5 * g * (2.0 * H[0, 1] * dgam + H[1, 1] * 2.0 * gam * dgam)
        return np.append(-H.ravel() / tau, power)

    T = 2.0 * np.pi / omega
    y7 = solve_ivp(rhs, (0.0, 7 * T), np.zeros(10), rtol=1e-10, atol=1e-13).y[:, -1]
    y7[9] = 0.0
    return float(solve_ivp(rhs, (7 * T, 8 * T), y7, rtol=1e-10, atol=1e-13).y[9, -1])


def test_finite_shear_closed_form_meets_the_ode_and_the_small_strain_limit():
    """The Fourier closed form of ``verify relaxation`` (finite_shear_cycle_energy): within
    1e-6 of the integrated ODE at gamma0 = 1, and pi gamma0^2 G'' within 1e-6 at 1e-4."""
    tau, omega = 0.05, 20.0
    g = relative_moduli([0.6])[0]
    exact = finite_shear_cycle_energy(M1, [0.6], [tau], omega=omega, gamma0=1.0)
    ode = finite_shear_cycle_work_ode(1.0, omega, g, tau)
    assert abs(exact / ode - 1.0) < 1e-6, (exact, ode)
    small = finite_shear_cycle_energy(M1, [0.6], [tau], omega=omega, gamma0=1e-4)
    _, G2, _ = harmonic_exact(omega, [0.6], [tau])
    assert abs(small / (np.pi * 1e-8 * G2) - 1.0) < 1e-6


@pytest.mark.parametrize("gamma0", [0.5, 1.0])
def test_finite_strain_dissipation_balances_the_cycle_work(gamma0):
    """Simple shear of amplitude 0.5 and 1 (one Prony term, omega tau = 1), 64 steps a cycle:
    the viscous energy the history reports over the steady cycle and the loop area of the
    boundary work both within 1 % of the closed form (the small-strain density |H|^2 / (2 G tau)
    gave +28 % and +127 %), and the two within 0.1 % of each other (the discrete balance)."""
    tau, omega = 0.05, 20.0
    exact = finite_shear_cycle_work_ode(gamma0, omega, relative_moduli([0.6])[0], tau)
    r = finite_harmonic_shear(M1, [0.6], [tau], omega=omega, gamma0=gamma0, per_cycle=64)
    assert abs(r["energy_per_cycle"] / exact - 1.0) < 0.01, (r, exact)
    assert abs(r["loop_area"] / exact - 1.0) < 0.01, (r, exact)
    assert abs(r["energy_per_cycle"] / r["loop_area"] - 1.0) < 1e-3, r


def test_finite_strain_dissipation_is_second_order_in_the_step():
    """Cycle dissipation at gamma0 = 1 with 32 and 64 steps a cycle: the error against the
    ODE oracle falls by 4 (order 1.7 .. 2.3), the history update and the trapezoidal work."""
    tau, omega = 0.05, 20.0
    exact = finite_shear_cycle_work_ode(1.0, omega, relative_moduli([0.6])[0], tau)
    err = [abs(finite_harmonic_shear(M1, [0.6], [tau], omega=omega, gamma0=1.0,
                                     per_cycle=n)["energy_per_cycle"] / exact - 1.0)
           for n in (32, 64)]
    order = np.log2(err[0] / err[1])
    assert 1.7 < order < 2.3, (err, order)
