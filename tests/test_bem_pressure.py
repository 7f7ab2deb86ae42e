"""The frictionless pressure branch (thesis 6.2.2, eq. 6.11) against a periodic FFT BEM.

The BEM (``driver.verification.bem_pressure.bem_contact``) is first checked against Westergaard's
closed form; the FE runs are then compared with it on a small-slope self-affine profile.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.verification.bem_pressure import bem_contact, compare


@pytest.mark.parametrize("fraction", [0.1, 0.25, 0.5])
def test_bem_matches_westergaard(fraction):
    """Elastic half-plane on a rigid sinusoid g cos(2 pi x / lam) (Johnson 1985, 13.1): at mean
    pressure p = p* sin^2(pi a / lam), p* = pi E* g / lam, the contact is 2a long and the peak
    pressure is 2 p / sin(pi a / lam).  Contact fraction within one grid cell (1/1024) and the
    peak pressure within 1e-4."""
    lam, g, e_star, n = 1.0, 0.01, 4.0, 1024
    x = np.arange(n) * lam / n
    a = 0.5 * fraction * lam
    s = np.sin(np.pi * a / lam)
    p_mean = np.pi * e_star * g / lam * s**2
    p, frac = bem_contact(g * np.cos(2.0 * np.pi * x / lam), lam, e_star, p_mean)
    assert abs(frac - fraction) <= 1.0 / n + 1e-12
    assert abs(p.max() - 2.0 * p_mean / s) < 1e-4 * (2.0 * p_mean / s)
    assert abs(p.mean() - p_mean) < 1e-12 * p_mean


def _assert_close(row: dict, tol: float) -> None:
    assert row["status"] == "ok", row["reason"]
    a, pc = row["bem_fraction"], row["bem_contact_pressure"]
    assert abs(row["fe_fraction"] - a) < tol * a, (row["fe_fraction"], a)
    assert abs(row["fe_contact_pressure"] - pc) < tol * pc, (row["fe_contact_pressure"], pc)


def test_pressure_branch_matches_bem_at_20_and_30_percent_contact():
    """rms slope 0.03, one mortar element per profile segment (64 per period), elastic m1, the
    window one whole period (offsets averaged): at BEM contact 20 % and 30 % the contact
    fraction and the mean contact pressure (eq. 6.11) within 3 % (measured -2.5 % / +2.6 % and
    +0.8 % / -0.7 %; with two elements per segment +1.7 % / -1.7 % and -2.9 % / +3.0 %)."""
    for row in compare(fractions=(0.20, 0.30), n=64)["rows"]:
        _assert_close(row, 0.03)


@pytest.mark.slow
def test_pressure_branch_matches_bem_refined_and_at_low_load():
    """Two elements per profile segment at BEM contact 20 %: within 3 % (measured +1.7 %,
    -1.7 %).  At 7 % contact (about 9 contact nodes in a few patches) a patch edge counts a node
    more or less depending on the road's offset against the mesh (the contact length alternates
    0.0547 / 0.0703 from one sliding step to the next), an O(h) error of the node count: measured
    +0.9 % with one element per segment, -11 % with two; checked within 15 %."""
    _assert_close(compare(fractions=(0.20,), n=64, refine=2)["rows"][0], 0.03)
    _assert_close(compare(fractions=(0.07,), n=64, refine=2)["rows"][0], 0.15)
