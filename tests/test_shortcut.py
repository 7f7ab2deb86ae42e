"""The full-contact closed form that may replace a frictionless FE run (driver.sliding.shortcut):
its criterion, and its guard against converged FE runs on the cases it admits (within 2 %)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rubberfriction.driver.sliding import shortcut
from rubberfriction.driver.sliding.run import run_sliding
from rubberfriction.driver.sliding.sinusoid import effective_modulus
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.forms.material_files import load_compound

L = 1.0  # mm, the cell period
WAVES = ((1, 0.004, 0.0), (2, 0.002, 1.0), (3, 0.0012, 2.5))  # (harmonic, amplitude mm, phase)


def surface(scale: float, n: int = 192) -> tuple[np.ndarray, np.ndarray]:
    x = np.arange(n) * L / n
    h = sum(a * scale * np.cos(2 * math.pi * k * x / L + ph) for k, a, ph in WAVES)
    return x, h


def spec(pressure: float, velocity: float, scale: float = 1.0, **kw) -> SlidingSpec:
    x, h = surface(scale)
    return SlidingSpec(surface_x=x, surface_h=h, period=L, pressure=pressure, velocity=velocity,
                       compound=load_compound("tread_default"), h_contact=L / 48,
                       slide_distance=8 * L, converge_tol=0.005, steady_state=True, **kw)


def closed_form(s: SlidingSpec) -> float:
    """mu = sum_k (q_k A_k)^2 Im E*_eff(q_k v) / (4 p0), written out for the three waves."""
    total = 0.0
    for k, a, _ in WAVES:
        q = 2 * math.pi * k / L
        total += (q * a) ** 2 * effective_modulus(s.compound, q * s.velocity).imag
    return total / (4.0 * s.pressure)


def test_criterion_admits_full_contact_over_small_slopes_only() -> None:
    ok = shortcut.check(spec(0.4, 10.0))
    assert ok.admitted and ok.p_min_ratio >= shortcut.MIN_PRESSURE_RATIO
    assert ok.mu == pytest.approx(closed_form(spec(0.4, 10.0)), rel=1e-9)
    assert ok.rms_slope < shortcut.MAX_RMS_SLOPE
    low = shortcut.check(spec(0.02, 10.0))  # partial contact at this pressure
    assert not low.admitted and "full contact" in low.reason and low.p_min_ratio < 0.2
    steep = shortcut.check(spec(40.0, 10.0, scale=4.0))
    assert not steep.admitted and "slopes" in steep.reason
    assert not shortcut.check(spec(0.4, 10.0, friction=0.3)).admitted


@pytest.mark.slow
@pytest.mark.parametrize("velocity,pressure", [(10.0, 0.4), (1000.0, 1.5)])
def test_admitted_cases_match_converged_fe_runs_within_two_percent(velocity: float,
                                                                   pressure: float) -> None:
    """The guard of the switch: on admitted cases the closed form and the converged FE run
    (16 elements on the shortest wave, converged window, periodic steady state) agree within
    2 %, across the loss peak of the compound (10 and 1000 mm/s)."""
    s = spec(pressure, velocity)
    admitted = shortcut.check(s)
    assert admitted.admitted
    fe = run_sliding(s)
    assert fe.ok and fe.converged == 1.0 and fe.contact_fraction == pytest.approx(1.0, abs=1e-3)
    assert admitted.mu == pytest.approx(closed_form(s), rel=1e-9)
    assert admitted.mu == pytest.approx(fe.mu_force, rel=0.02)
    via = run_sliding(SlidingSpec(**{**vars(s), "shortcut": True}))
    assert via.stats["shortcut"] == 1.0 and via.mu_force == admitted.mu
