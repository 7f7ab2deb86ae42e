"""Hertz: plane-strain cylinder on a rigid flat, a = sqrt(4PR/(pi E*)), p0 = 2P/(pi a).

Within 2 % at the finest of four refinements (4..32 elements per half-width), for nu = 0.3 and
nearly incompressible (nu = 0.4999, mixed Q1P0); the errors of the finest level are below those of
the coarsest and the L2 pressure error drops by more than 3x.  (Level to level the error is not
monotone: the contact edge falls anywhere between two nodes.)
"""

from __future__ import annotations

import pytest

from rubberfriction.driver.verification import contact_cases as cc


@pytest.mark.parametrize("nu", [0.3, 0.4999])
def test_hertz_within_two_percent_and_converging(nu):
    r = cc.hertz(nu=nu, elements_per_a=(4, 8, 16, 32))
    by = {c["quantity"]: c for c in r["checks"]}
    assert by["half-width a"]["passed"], by["half-width a"]
    assert by["peak pressure p0"]["passed"], by["peak pressure p0"]
    coarse, fine = r["runs"][0], r["runs"][-1]
    assert max(fine["err_a"], fine["err_p0"]) < max(coarse["err_a"], coarse["err_p0"])
    assert fine["err_l2"] < coarse["err_l2"] / 3.0
    assert abs(fine["P"] - r["parameters"]["P"]) <= 5e-3 * r["parameters"]["P"]


def test_hertz_node_to_segment_also_within_two_percent():
    r = cc.hertz(nu=0.3, elements_per_a=(8, 32), method="nts")
    for c in r["checks"]:
        if c.get("tolerance") is not None:
            assert c["passed"], c
