"""Westergaard: elastic layer on the periodic rigid sinusoid z = h cos(2 pi x/lambda).

p* = pi E* h/lambda, p_mean = p* sin^2(pi a/lambda): within 2 % for partial contact at
p_mean/p* = 0.1, 0.4, 0.8 (nearly incompressible, Q1P0) and for nu = 0.3.  The master is one
period of the sinusoid, wrapped periodically; the layer is one wavelength wide with periodic
sides.
"""

from __future__ import annotations

import pytest

from rubberfriction.driver.verification import contact_cases as cc


@pytest.mark.parametrize("p_ratio,nu", [(0.1, 0.4999), (0.4, 0.4999), (0.8, 0.4999), (0.4, 0.3)])
def test_westergaard_within_two_percent(p_ratio, nu):
    r = cc.westergaard(p_ratio=p_ratio, nu=nu)
    for c in r["checks"]:
        if c.get("tolerance") is not None:
            assert c["passed"], c
