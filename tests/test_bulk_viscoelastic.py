"""Finite linear viscoelasticity (eqs. 3.72-3.78) against the linear closed forms.

Calls the same code as ``rubberfriction verify relaxation``.  Homogeneous shear of amplitude 1e-5:
the finite-strain model equals linear viscoelasticity up to O(gamma^2) ~ 1e-10.  Two history
schemes: the thesis' midpoint rule (3.76) and the default one exact for Sbar linear in time.
"""

import numpy as np
import pytest

from rubberfriction.driver.verification.relaxation import harmonic_shear, ramp_hold
from rubberfriction.forms.compound import MooneyRivlin

M1 = MooneyRivlin(0.174, 0.300, 0.0208)  # compound m1, table C.2
GAMMA_K, TAU_K = [0.5, 0.3], [0.01, 0.1]


def test_relaxation_midpoint_within_one_percent_and_second_order():
    """Midpoint rule: ramp over tau_min/10 then hold is within 1 % at all times; error ~ dt^2."""
    t_ramp = TAU_K[0] / 10.0
    e1 = ramp_hold(M1, GAMMA_K, TAU_K, dt=t_ramp, t_ramp=t_ramp, t_end=0.3, scheme="midpoint")
    e2 = ramp_hold(M1, GAMMA_K, TAU_K, dt=t_ramp / 2.0, t_ramp=t_ramp, t_end=0.3, scheme="midpoint")
    assert e1["max_rel_error"] < 0.01, e1["max_rel_error"]
    order = np.log2(e1["max_rel_error"] / e2["max_rel_error"])
    assert 1.8 < order < 2.2, order


def test_relaxation_linear_scheme_exact_for_ramps():
    """The default scheme integrates a linear-in-time strain exactly: round-off only, any dt/tau."""
    for dt in (TAU_K[0] / 10.0, 3.0 * TAU_K[0]):
        e = ramp_hold(M1, GAMMA_K, TAU_K, dt=dt, t_ramp=dt, t_end=0.3, scheme="linear")
        assert e["max_rel_error"] < 1e-7, (dt, e["max_rel_error"])


@pytest.mark.parametrize("scheme", ["linear", "midpoint"])
def test_harmonic_shear_second_order(scheme):
    """Smooth input: both schemes converge at second order in dt (G'' at omega tau = 1)."""
    tau = 0.05
    err = []
    for per_cycle in (16, 32):
        h = harmonic_shear(M1, [0.6], [tau], omega=1.0 / tau, per_cycle=per_cycle, cycles=6, scheme=scheme)
        err.append(abs(h["G_loss"] - h["G_loss_exact"]) / h["G_loss_exact"])
    order = np.log2(err[0] / err[1])
    assert 1.7 < order < 2.3, (err, order)


@pytest.mark.parametrize("omega_tau", [0.1, 1.0, 10.0])
def test_harmonic_shear_storage_loss_and_dissipation(omega_tau):
    """G', G'' within 1 % of eq. (3.34); energy per cycle and loop area = pi gamma0^2 G'' within 1 %."""
    tau = 0.05
    h = harmonic_shear(M1, [0.6], [tau], omega=omega_tau / tau)
    assert abs(h["G_storage"] - h["G_storage_exact"]) < 0.01 * h["G_storage_exact"]
    assert abs(h["G_loss"] - h["G_loss_exact"]) < 0.01 * h["G_loss_exact"]
    assert abs(h["energy_per_cycle"] - h["energy_exact"]) < 0.01 * h["energy_exact"]
    assert abs(h["loop_area"] - h["energy_exact"]) < 0.01 * h["energy_exact"]
