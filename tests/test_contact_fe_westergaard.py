"""Westergaard: elastic layer on the periodic rigid sinusoid z = h cos(2 pi x/lambda).

Closed form (Johnson, Contact Mechanics, 13.2, partial contact of an elastic half-plane):

    E* = E/(1 - nu^2),  p* = pi E* h/lambda,  p_mean = p* sin^2(pi a/lambda),
    p_max = 2 p_mean/sin(pi a/lambda)

evaluated here at the mean pressure the FE contact actually carries (F_z/lambda, within 0.2 % of
the target p_ratio p*), for partial contact at p_mean/p* = 0.1, 0.4, 0.8 (nearly incompressible,
Q1P0; within 1 %, achieved <= 0.24 %) and 0.4 with nu = 0.3 (within 2 %, achieved 0.9 %; the
case's own tolerance is 2 %).  The master is one period of the sinusoid, wrapped periodically; the
layer is one wavelength wide with periodic sides and 2 wavelengths thick.  Computed: the half-width
from the pressure moment Int p sin^2(pi x/lambda) / Int p = sin^2(pi a/lambda)/4, the peak as the
pressure of the node at the crest.
"""

from __future__ import annotations

import math

import pytest

from fe_helpers import checks_of, rel
from rubberfriction.driver.verification.westergaard import westergaard

E, WAVELENGTH, AMPLITUDE = 6.0, 1.0, 0.005
CHECKS = {"half-width a", "p_mean = p* sin^2(pi a/lam)", "peak pressure", "contact length / 2"}


@pytest.mark.parametrize("p_ratio,nu,tol", [(0.1, 0.4999, 0.01), (0.4, 0.4999, 0.01),
                                            (0.8, 0.4999, 0.01), (0.4, 0.3, 0.02)])
def test_westergaard(p_ratio, nu, tol):
    r = westergaard(E=E, nu=nu, wavelength=WAVELENGTH, amplitude=AMPLITUDE, p_ratio=p_ratio)
    by = checks_of(r, CHECKS)
    p_star = math.pi * E / (1.0 - nu * nu) * AMPLITUDE / WAVELENGTH
    # the carried mean pressure F_z/lambda is reported as the reference of the p_mean check
    p_mean = by["p_mean = p* sin^2(pi a/lam)"]["analytical"]
    assert rel(p_mean, p_ratio * p_star) <= 2e-3
    s = math.sqrt(p_mean / p_star)
    a_exact = WAVELENGTH / math.pi * math.asin(s)
    a = by["half-width a"]["computed"]
    assert rel(a, a_exact) <= tol, (a, a_exact)
    assert rel(p_star * math.sin(math.pi * a / WAVELENGTH) ** 2, p_mean) <= tol
    assert rel(by["peak pressure"]["computed"], 2.0 * p_mean / s) <= tol, \
        (by["peak pressure"], 2.0 * p_mean / s)
