"""Hertz: plane-strain cylinder (radius R) on a rigid flat, load P per unit depth (frictionless).

Closed form (Johnson, Contact Mechanics, ch. 4: line contact of cylinders, here one body rigid):

    E* = E/(1 - nu^2),   a = sqrt(4 P R/(pi E*)),   p0 = 2 P/(pi a)

evaluated here at the load P the FE contact actually carries (within 0.5 % of the target, the
load giving a = 0.02 R).  Within 1 % at the finest of four refinements (4..32 elements per
half-width; the case's own tolerance is 2 %, achieved <= 0.5 %), for nu = 0.3 and nearly
incompressible (nu = 0.4999, mixed Q1P0); the errors of the finest level are below those of the
coarsest and the L2 pressure error drops by more than 3x.  (Level to level the error is not
monotone: the contact edge falls anywhere between two nodes.)  Computed: the half-width from the
second moment of the nodal pressures (Int p x^2 / Int p = a^2/4), p0 the pressure of the node at
x = 0.
"""

from __future__ import annotations

import math

import pytest

from fe_helpers import checks_of, rel
from rubberfriction.driver.verification.hertz import hertz

R, E, A_OVER_R = 10.0, 6.0, 0.02
TOL = 0.01  # product: 0.02
HERTZ_CHECKS = {"half-width a", "peak pressure p0", "L2 pressure error", "L2 error finest/coarsest"}


def hertz_exact(P: float, nu: float) -> tuple[float, float]:
    E_star = E / (1.0 - nu * nu)
    a = math.sqrt(4.0 * P * R / (math.pi * E_star))
    return a, 2.0 * P / (math.pi * a)


def target_load(nu: float) -> float:
    """The load of a = A_OVER_R R: P = pi E* a^2/(4 R)."""
    return math.pi * E / (1.0 - nu * nu) * (A_OVER_R * R) ** 2 / (4.0 * R)


def errors(run: dict, nu: float) -> tuple[float, float]:
    a, p0 = hertz_exact(run["P"], nu)
    return rel(run["a"], a), rel(run["p0"], p0)


@pytest.mark.parametrize("nu", [0.3, 0.4999])
def test_hertz_within_one_percent_and_converging(nu):
    r = hertz(R=R, E=E, nu=nu, a_over_R=A_OVER_R, elements_per_a=(4, 8, 16, 32))
    by = checks_of(r, HERTZ_CHECKS)
    P = target_load(nu)
    assert rel(r["parameters"]["P"], P) < 1e-12
    runs = r["runs"]
    assert [round(x["elements_per_a"]) for x in runs] == [4, 8, 16, 32]
    coarse, fine = runs[0], runs[-1]
    for run in runs:
        assert rel(run["P"], P) <= 5e-3  # the load carried
    a, p0 = hertz_exact(fine["P"], nu)
    assert (by["half-width a"]["computed"] == fine["a"]
            and by["peak pressure p0"]["computed"] == fine["p0"])
    assert rel(fine["a"], a) <= TOL, (fine["a"], a)
    assert rel(fine["p0"], p0) <= TOL, (fine["p0"], p0)
    assert max(errors(fine, nu)) < max(errors(coarse, nu))
    # L2 error of the nodal pressures against the exact elliptic pressure (mortar-averaged),
    # computed by the case: the nodal pressures are not in its result
    assert fine["err_l2"] < coarse["err_l2"] / 3.0


def test_hertz_node_to_segment_also_within_one_percent():
    nu = 0.3
    r = hertz(R=R, E=E, nu=nu, a_over_R=A_OVER_R, elements_per_a=(8, 32), method="nts")
    checks_of(r, HERTZ_CHECKS)
    fine = r["runs"][-1]
    assert round(fine["elements_per_a"]) == 32 and rel(fine["P"], target_load(nu)) <= 5e-3
    err_a, err_p0 = errors(fine, nu)
    assert err_a <= TOL and err_p0 <= TOL, (err_a, err_p0)
