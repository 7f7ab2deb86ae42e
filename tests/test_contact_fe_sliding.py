"""Coulomb sliding block: F_x/F_z = mu within 0.5 % -- constant mu on a finite block (rounded
front edge, as the thesis' samples) and a mu(p, v) spline at the known (p, v) of a periodic layer
in steady sliding -- and Newton convergence in sliding steps.  The convergence order is estimated
from the last three residuals above round-off; it is ~2 (quadratic) but the three-point estimate
is noisy, so the tests require >= 1.6."""

from __future__ import annotations

import pytest

from rubberfriction.driver.verification import contact_cases as cc


@pytest.mark.parametrize("method,n_contact", [("mortar", 16), ("nts", 32)])
def test_sliding_block(method, n_contact):
    r = cc.sliding_block(method=method, n_contact=n_contact)
    by = {c["quantity"]: c for c in r["checks"]}
    for c in r["checks"]:
        if c.get("tolerance") is not None:
            assert c["passed"], c
    assert by["layer: pressure spread"]["computed"] < 1e-8  # uniform p: the (p, v) is known
    assert by["Newton order, finite block"]["computed"] >= 1.6, r["newton"]["finite"]
    assert by["Newton order, layer mu(p,v)"]["computed"] >= 1.6, r["newton"]["periodic"]
