"""Model only what a run requires: the linear viscoelastic closed form for full contact.

A frictionless periodic cell whose surface has small slopes and stays in full contact is a
linear problem: every harmonic of the surface, h(x) = sum_k Re[2 c_k exp(i q_k x)],
q_k = 2 pi k / L, loads the half-plane independently at its own frequency omega_k = q_k v (steady
sliding at v),
with the pressure perturbation p_k = E*_eff(omega_k) q_k 2 c_k / 2 (the single-sinusoid closed
form of ``driver.sliding.sinusoid``, superposed).  The homogenised coefficient of friction
(eq. 6.2) and the mean contact pressure (eq. 6.11) are then

    mu = sum_k (q_k |2 c_k|)^2 Im E*_eff(q_k v) / (4 p0),     p_avg = p0,   A_c / A_0 = 1,

with E*_eff of the FE material model (elastic volume, WLF at the run's temperature).  Cross terms
of different harmonics average to zero over a period.

The shortcut replaces the FE run only where the criterion :func:`check` admits it; the guard
test (``tests/test_shortcut.py``) compares admitted cases with converged FE runs within 2 %:

* frictionless, periodic cell, uniform surface sampling, no thermal partitions;
* small slopes: rms slope <= ``MAX_RMS_SLOPE`` and largest slope <= ``MAX_SLOPE`` (the finite-strain
  and geometric corrections are O(slope^2));
* full contact with margin: the linear pressure stays above ``MIN_PRESSURE_RATIO`` p0 everywhere
  (contact loss would make the problem nonlinear);
* block height >= period (the finite-height correction of the longest wave, exp(-2 pi H/L), is
  below 0.2 %).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubberfriction.driver.sliding.sinusoid import effective_modulus
from rubberfriction.driver.sliding.spec import SlidingResult, SlidingSpec

MAX_RMS_SLOPE = 0.05
MAX_SLOPE = 0.15
MIN_PRESSURE_RATIO = 0.2


@dataclass(frozen=True)
class ShortcutCheck:
    """Whether the closed form may replace the FE run, why, and its values."""

    admitted: bool
    reason: str
    mu: float = float("nan")
    p_min_ratio: float = float("nan")  # min_x p(x) / p0 of the linear solution
    rms_slope: float = float("nan")
    max_slope: float = float("nan")


def _harmonics(spec: SlidingSpec) -> tuple[np.ndarray, np.ndarray] | None:
    """(q_k, 2 c_k) for k = 1 .. N/2 of a uniformly sampled period, None if not uniform."""
    x, h, L = np.asarray(spec.surface_x, float), np.asarray(spec.surface_h, float), spec.period
    n = x.size
    if n < 4 or not np.allclose(np.diff(x), L / n, rtol=1e-6, atol=0.0):
        return None
    c = np.fft.rfft(h) / n
    amp = 2.0 * c[1:]
    if n % 2 == 0:
        amp[-1] *= 0.5  # the Nyquist harmonic is real: counted once
    return 2.0 * np.pi * np.arange(1, amp.size + 1) / L, amp


def check(spec: SlidingSpec) -> ShortcutCheck:
    """The criterion of the module docstring, with the closed-form values when admitted."""
    if spec.friction is not None:
        return ShortcutCheck(False, "friction in the contact")
    if not spec.period > 0:
        return ShortcutCheck(False, "not a periodic cell")
    if (spec.block_height or spec.block_length or spec.period) < spec.period:
        return ShortcutCheck(False, "block lower than its period")
    if spec.temperature_layers:
        return ShortcutCheck(False, "temperature layers (the closed form is for one temperature)")
    harmonics = _harmonics(spec)
    if harmonics is None:
        return ShortcutCheck(False, "surface not uniformly sampled")
    q, amp = harmonics
    slope_k = q * amp  # complex slope amplitudes
    rms = float(np.sqrt(0.5 * np.sum(np.abs(slope_k) ** 2)))
    x = np.linspace(0.0, spec.period, 8 * q.size, endpoint=False)
    phase = np.exp(1j * np.outer(x, q))
    max_slope = float(np.max(np.abs((phase * (1j * slope_k)).real.sum(axis=1))))
    E = np.array([effective_modulus(spec.compound, qk * spec.velocity, spec.temperature)
                  for qk in q])
    p = spec.pressure + (phase * (0.5 * E * q * amp)).real.sum(axis=1)
    p_min = float(p.min() / spec.pressure)
    mu = float(np.sum(np.abs(slope_k) ** 2 * E.imag) / (4.0 * spec.pressure))
    values = {"mu": mu, "p_min_ratio": p_min, "rms_slope": rms, "max_slope": max_slope}
    if rms > MAX_RMS_SLOPE or max_slope > MAX_SLOPE:
        return ShortcutCheck(False, f"slopes too large (rms {rms:.3g}, max {max_slope:.3g})",
                             **values)
    if p_min < MIN_PRESSURE_RATIO:
        return ShortcutCheck(False, f"not in full contact with margin (p_min / p0 = {p_min:.3g})",
                             **values)
    return ShortcutCheck(True, "full contact, small slopes", **values)


def closed_form_result(spec: SlidingSpec, c: ShortcutCheck) -> SlidingResult:
    """The run's result from the closed form (stats say so: ``shortcut`` = 1)."""
    res = SlidingResult("ok", mu_force=c.mu, mu_energy=c.mu, mean_pressure=spec.pressure,
                        contact_fraction=1.0, window_drift=0.0, mu_error=0.0, contact_drift=0.0,
                        contact_error=0.0, converged=1.0,
                        stabilisation_share=0.0)
    res.stats = {"shortcut": 1.0, "attempt": "closed form", "p_min_ratio": c.p_min_ratio,
                 "rms_slope": c.rms_slope, "max_slope": c.max_slope, "wall_time": 0.0}
    return res
